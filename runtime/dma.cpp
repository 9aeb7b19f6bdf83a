#include "runtime/dma.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "runtime/check.h"

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace ardcell {
namespace {

constexpr int kLine = int(Dma::kAlignBytes / sizeof(float));

[[maybe_unused]] void check_transfer(const void* local, const void* remote, std::size_t bytes,
                                     int tag, const char* what) {
  const auto misaligned = [](const void* p) {
    return reinterpret_cast<std::uintptr_t>(p) % Dma::kAlignBytes != 0;
  };
  const char* why = nullptr;
  if (bytes > Dma::kMaxTransferBytes)
    why = "larger than 16 KiB";
  else if (bytes == 0 || bytes % Dma::kAlignBytes != 0)
    why = "size not a positive multiple of 128 bytes";
  else if (misaligned(local))
    why = "local address not 128-byte aligned";
  else if (misaligned(remote))
    why = "remote address not 128-byte aligned";
  else if (tag < 0 || tag >= Dma::kTags)
    why = "tag outside 0..31";
  if (why) {
    std::fprintf(stderr,
                 "ardcell: Dma %s rejected: %s (%zu bytes, local %p, remote %p, tag %d); "
                 "transfers are at most 16384 bytes, 128-byte aligned\n",
                 what, why, bytes, local, remote, tag);
    std::abort();
  }
}

// First and one-past-last x of the whole 128-byte lines covering [x0, x1) in a row whose
// element -field_halo sits on a line boundary.
inline void line_span(int x0, int x1, int field_halo, int& a0, int& a1) {
  // Floor division: periodic boxes may reach past the stored halo (negative offsets).
  const auto floor_div = [](int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
  a0 = floor_div(x0 + field_halo, kLine) * kLine - field_halo;
  a1 = floor_div(x1 + field_halo + kLine - 1, kLine) * kLine - field_halo;
}

// The copy of one transfer. A put into a field too large to stay in the caches is written with
// non-temporal stores: the field's lines are not read in first (no read-for-ownership), so a
// put costs its bytes of DRAM traffic once instead of twice. Transfers are whole 128-byte lines
// at 128-byte aligned addresses, so the streaming copy needs no edge cases.
inline void copy_transfer(void* dst, const void* src, std::size_t bytes, bool streaming) {
#if defined(__AVX512F__)
  if (streaming) {
    auto* d = static_cast<float*>(dst);
    const auto* s = static_cast<const float*>(src);
    for (std::size_t i = 0; i < bytes / sizeof(float); i += 16)
      _mm512_stream_ps(d + i, _mm512_loadu_ps(s + i));
    return;
  }
#else
  (void)streaming;
#endif
  std::memcpy(dst, src, bytes);
}

// Non-temporal stores are weakly ordered: fence them before the worker reports completion.
inline void fence_streaming_stores() {
#if defined(__AVX512F__)
  _mm_sfence();
#endif
}

}  // namespace

void Dma::enqueue(void* dst, const void* src, std::size_t bytes, int tag, const char* what,
                  bool streaming) {
#if defined(ARDCELL_CHECKS) && ARDCELL_CHECKS
  check_transfer(what[0] == 'g' ? dst : src, what[0] == 'g' ? src : dst, bytes, tag, what);
#else
  (void)what;
#endif
  if (count_ == kQueueCapacity) complete(0);  // the MFC queue is full: the oldest one lands
  queue_[count_++] = Transfer{dst, src, std::uint32_t(bytes), tag, streaming};
  // Software prefetch of the source lines: the copy at wait() then runs from cache.
  const char* s = static_cast<const char*>(src);
  for (std::size_t off = 0; off < bytes; off += 64) __builtin_prefetch(s + off, 0, 3);
  ++transfers_;
}

void Dma::complete(int index) {
  const Transfer& t = queue_[index];
  copy_transfer(t.dst, t.src, t.bytes, t.streaming);
  if (t.streaming) fence_streaming_stores();
  queue_[index] = queue_[--count_];
}

void Dma::get(void* local, const void* remote, std::size_t bytes, int tag) {
  enqueue(local, remote, bytes, tag, "get");
  bytes_in_ += bytes;
}

void Dma::put(const void* local, void* remote, std::size_t bytes, int tag) {
  enqueue(remote, local, bytes, tag, "put");
  bytes_out_ += bytes;
}

void Dma::wait(int tag) {
  // Transfers of one tag land in issue order: scan forward, keeping the others' order intact.
  int kept = 0;
  bool streamed = false;
  for (int i = 0; i < count_; ++i) {
    const Transfer& t = queue_[i];
    if (t.tag == tag) {
      copy_transfer(t.dst, t.src, t.bytes, t.streaming);
      streamed = streamed || t.streaming;
    } else {
      queue_[kept++] = t;
    }
  }
  count_ = kept;
  if (streamed) fence_streaming_stores();
}

void Dma::wait_all() {
  bool streamed = false;
  for (int i = 0; i < count_; ++i) {
    copy_transfer(queue_[i].dst, queue_[i].src, queue_[i].bytes, queue_[i].streaming);
    streamed = streamed || queue_[i].streaming;
  }
  count_ = 0;
  if (streamed) fence_streaming_stores();
}

View<float> Dma::local_box(int field_halo, const Box2& box, SlotArena& arena) const {
  int a0, a1;
  line_span(box.min.x, box.max.x, field_halo, a0, a1);
  const std::ptrdiff_t stride = a1 - a0;
  auto* data = reinterpret_cast<float*>(
      arena.allocate(std::size_t(stride) * std::size_t(box.height()) * sizeof(float)));
  const Box2 lines{{a0, box.min.y}, {a1, box.max.y}};
  return View<float>(data, stride, lines).crop(box);
}

View<float> Dma::get_box(const FieldF& field, const Box2& box, SlotArena& arena, int tag) {
  ARDCELL_DCHECK(field.with_halo().contains(box), "Dma::get_box outside the field");
  View<float> local = local_box(field, box, arena);
  if (box.empty()) return local;
  int a0, a1;
  line_span(box.min.x, box.max.x, field.halo(), a0, a1);
  const std::size_t bytes = std::size_t(a1 - a0) * sizeof(float);
  for (int y = box.min.y; y < box.max.y; ++y) get(local.row(y) + a0, field.row(y) + a0, bytes, tag);
  return local;
}

View<float> Dma::get_box_periodic(const FieldF& field, const Box2& box, SlotArena& arena, int tag) {
  View<float> local = local_box(field, box, arena);
  if (box.empty()) return local;
  const int nx = field.nx(), ny = field.ny();
  ARDCELL_CHECK(nx > 0 && ny > 0, "periodic fetch of an empty field");
  // Rows wrap whole: each is one line-aligned transfer of the interior columns it needs;
  // columns past the left or right edge are copied from the far side once the rows land.
  const int x0 = std::max(box.min.x, 0), x1 = std::min(box.max.x, nx);
  const bool wraps_x = box.min.x < 0 || box.max.x > nx;
  if (x0 < x1) {
    int a0, a1;
    line_span(x0, x1, field.halo(), a0, a1);
    const std::size_t bytes = std::size_t(a1 - a0) * sizeof(float);
    for (int y = box.min.y; y < box.max.y; ++y) {
      const int sy = ((y % ny) + ny) % ny;
      get(local.row(y) + a0, field.row(sy) + a0, bytes, tag);
    }
  }
  if (wraps_x) {
    // The wrapped columns are a handful of cells per row: an element-wise copy (the DMA list's
    // short elements) after the rows have landed, since the line-widened rows overlap them.
    wait(tag);
    for (int y = box.min.y; y < box.max.y; ++y) {
      const int sy = ((y % ny) + ny) % ny;
      const float* src = field.row(sy);
      float* dst = local.row(y);
      for (int x = box.min.x; x < box.max.x; ++x)
        if (x < 0 || x >= nx) dst[x] = src[((x % nx) + nx) % nx];
    }
  }
  return local;
}

void Dma::put_box(View<const float> local, FieldF& field, const Box2& box, int tag) {
  ARDCELL_DCHECK(field.with_halo().contains(box), "Dma::put_box outside the field");
  if (box.empty()) return;
  int a0, a1;
  line_span(box.min.x, box.max.x, field.halo(), a0, a1);
  // A put writes whole lines: the box must begin on a line and end on one or at the row's end,
  // or it would overwrite cells another tile owns.
  ARDCELL_CHECK(a0 == box.min.x && (a1 == box.max.x || box.max.x == field.nx() + field.halo()),
                "Dma::put_box: box must start and end on 128-byte lines (TilePlan's x cuts)");
  const std::size_t bytes = std::size_t(a1 - a0) * sizeof(float);
  const bool streaming = field.raw_size() * sizeof(float) >= kStreamingPutFieldBytes;
  for (int y = box.min.y; y < box.max.y; ++y) {
    enqueue(field.row(y) + a0, local.row(y) + a0, bytes, tag, "put", streaming);
    bytes_out_ += bytes;
  }
}

}  // namespace ardcell
