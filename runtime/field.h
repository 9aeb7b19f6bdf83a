#pragma once
// Field<T>: a 2D grid of cells that owns its interior and a halo of any width; View<T>: a
// non-owning window on a Field or on a local-store buffer. Both are indexed in global cell
// coordinates, so a kernel written against a View runs unchanged on a whole field or on a tile
// copied into a local store (the kernel never learns which).
//
// A field's interior is a box whose minimum may be negative or beyond 0 (a block of a larger
// domain, runtime/block_layout.h): cells keep their global coordinates everywhere.
//
// Storage: row-major, each row padded to a multiple of 128 bytes and 128-byte aligned, so that
// DMA transfers and SIMD loads of whole rows are aligned. Element (x, y) of a field with halo h
// over the interior [m, M) lives at data[(y - m.y + h) * stride + (x - m.x + h)].
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>

#include "runtime/box.h"
#include "runtime/check.h"

namespace ardcell {

inline constexpr std::size_t kRowAlignBytes = 128;

// A window of cells [box) over memory with a row stride in elements. data points at box.min.
template <class T>
class View {
 public:
  View() = default;
  View(T* data, std::ptrdiff_t stride, Box2 box) : data_(data), stride_(stride), box_(box) {}
  // A view of T converts to a view of const T.
  template <class U, class = std::enable_if_t<std::is_same_v<const U, T>>>
  View(const View<U>& v) : data_(v.data()), stride_(v.stride()), box_(v.box()) {}

  const Box2& box() const { return box_; }
  std::ptrdiff_t stride() const { return stride_; }
  T* data() const { return data_; }

  T& operator()(int x, int y) const {
    ARDCELL_DCHECK(box_.contains(Int2{x, y}), "View index outside its box");
    return data_[(y - box_.min.y) * stride_ + (x - box_.min.x)];
  }
  T& operator()(Int2 p) const { return (*this)(p.x, p.y); }

  // Pointer r such that r[x] is cell (x, y) for box().min.x <= x < box().max.x.
  T* row(int y) const {
    ARDCELL_DCHECK(y >= box_.min.y && y < box_.max.y, "View row outside its box");
    return data_ + ((y - box_.min.y) * stride_ - box_.min.x);
  }

  // The same memory restricted to b, which must lie inside box().
  View crop(const Box2& b) const {
    ARDCELL_CHECK(box_.contains(b), "View::crop outside the view");
    if (b.empty()) return View(data_, stride_, b);
    return View(data_ + (b.min.y - box_.min.y) * stride_ + (b.min.x - box_.min.x), stride_, b);
  }

 private:
  T* data_ = nullptr;
  std::ptrdiff_t stride_ = 0;
  Box2 box_{};
};

template <class T>
class Field {
  static_assert(std::is_trivially_copyable_v<T>, "Field holds plain numbers");

 public:
  Field() = default;
  // A field of size.x by size.y interior cells with `halo` cells on each side, zero-filled.
  Field(Int2 size, int halo) : Field(box_of_size(size), halo, 0) {}
  // The same over the interior cells `interior` (global coordinates).
  static Field over(Box2 interior, int halo) { return Field(interior, halo, 0); }
  Field(const Field& o) : Field(o.interior_, o.halo_, 0) { copy_storage_from(o); }
  Field& operator=(const Field& o) {
    if (this == &o) return *this;
    if (o.interior_ != interior_ || o.halo_ != halo_) *this = Field(o.interior_, o.halo_, 0);
    copy_storage_from(o);
    return *this;
  }
  Field(Field&&) noexcept = default;
  Field& operator=(Field&&) noexcept = default;

  Int2 size() const { return size_; }
  int nx() const { return size_.x; }
  int ny() const { return size_.y; }
  int halo() const { return halo_; }
  std::ptrdiff_t stride() const { return stride_; }
  bool empty() const { return !storage_; }

  Box2 interior() const { return interior_; }
  Int2 origin() const { return interior_.min; }
  Box2 with_halo() const { return interior().grown(halo_); }

  T& operator()(int x, int y) {
    ARDCELL_DCHECK(with_halo().contains(Int2{x, y}), "Field index outside interior + halo");
    return storage_.get()[(y - interior_.min.y + halo_) * stride_ + (x - interior_.min.x + halo_)];
  }
  const T& operator()(int x, int y) const { return const_cast<Field&>(*this)(x, y); }

  // Pointer r such that r[x] is cell (x, y), origin.x - halo <= x < origin.x + nx + halo.
  T* row(int y) {
    return storage_.get() + ((y - interior_.min.y + halo_) * stride_ + halo_ - interior_.min.x);
  }
  const T* row(int y) const { return const_cast<Field&>(*this).row(y); }

  // Views over interior + halo, or over a box inside it.
  View<T> view() { return View<T>(storage_.get(), stride_, with_halo()); }
  View<const T> view() const { return View<const T>(storage_.get(), stride_, with_halo()); }
  View<T> view(const Box2& b) { return view().crop(b); }
  View<const T> view(const Box2& b) const { return view().crop(b); }

  // The whole allocation, halo and padding included (for copies, checksums, I/O).
  T* raw() { return storage_.get(); }
  const T* raw() const { return storage_.get(); }
  std::size_t raw_size() const { return std::size_t(stride_ * rows_); }

  void fill(T value) {
    T* p = storage_.get();
    for (std::size_t i = 0, n = raw_size(); i < n; ++i) p[i] = value;
  }

 private:
  Field(Box2 interior, int halo, int /*primary*/)
      : interior_(interior), size_(interior.size()), halo_(halo) {
    const Int2 size = size_;
    ARDCELL_CHECK(size.x >= 0 && size.y >= 0 && halo >= 0, "Field size and halo must be >= 0");
    constexpr std::ptrdiff_t per_line = kRowAlignBytes / sizeof(T);
    const std::ptrdiff_t row = std::ptrdiff_t(size.x) + 2 * halo;
    stride_ = (row + per_line - 1) / per_line * per_line;
    if (stride_ == 0) stride_ = per_line;
    rows_ = std::ptrdiff_t(size.y) + 2 * halo;
    const std::size_t bytes = std::size_t(stride_ * rows_) * sizeof(T);
    void* p = bytes ? std::aligned_alloc(kRowAlignBytes, bytes) : nullptr;
    if (bytes && !p) throw std::bad_alloc();
    storage_.reset(static_cast<T*>(p));
    if (bytes) std::memset(p, 0, bytes);
  }
  struct FreeDeleter {
    void operator()(T* p) const { std::free(p); }
  };
  void copy_storage_from(const Field& o) {
    if (raw_size()) std::memcpy(storage_.get(), o.storage_.get(), raw_size() * sizeof(T));
  }

  Box2 interior_{};
  Int2 size_{};
  int halo_ = 0;
  std::ptrdiff_t stride_ = 0;
  std::ptrdiff_t rows_ = 0;
  std::unique_ptr<T, FreeDeleter> storage_;
};

using FieldF = Field<float>;
using ViewF = View<float>;
using ConstViewF = View<const float>;

// Copies the cells of `box` from src to dst (both views must contain box).
template <class T>
void copy_box(View<const T> src, View<T> dst, const Box2& box) {
  if (box.empty()) return;
  for (int y = box.min.y; y < box.max.y; ++y)
    std::memcpy(dst.row(y) + box.min.x, src.row(y) + box.min.x,
                std::size_t(box.width()) * sizeof(T));
}

}  // namespace ardcell
