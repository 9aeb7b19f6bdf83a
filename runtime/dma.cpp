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
// element row_start (a field's origin.x - halo) sits on a line boundary.
inline void line_span(int x0, int x1, int row_start, int& a0, int& a1) {
  a0 = (x0 - row_start) / kLine * kLine + row_start;
  a1 = (x1 - row_start + kLine - 1) / kLine * kLine + row_start;
}

int row_start(const FieldF& f) { return f.origin().x - f.halo(); }

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

View<float> Dma::local_box(int row_start, const Box2& box, SlotArena& arena) const {
  int a0, a1;
  line_span(box.min.x, box.max.x, row_start, a0, a1);
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
  line_span(box.min.x, box.max.x, row_start(field), a0, a1);
  const std::size_t bytes = std::size_t(a1 - a0) * sizeof(float);
  for (int y = box.min.y; y < box.max.y; ++y) get(local.row(y) + a0, field.row(y) + a0, bytes, tag);
  return local;
}

void Dma::put_box(View<const float> local, FieldF& field, const Box2& box, int tag) {
  ARDCELL_DCHECK(field.with_halo().contains(box), "Dma::put_box outside the field");
  if (box.empty()) return;
  int a0, a1;
  line_span(box.min.x, box.max.x, row_start(field), a0, a1);
  // A put writes whole lines: the box must begin on a line (or in the row's first line) and end
  // on one (or in the row's last), or it would overwrite cells another tile owns. The cells a
  // widened put writes past the box are halo cells nobody reads before they are filled again.
  ARDCELL_CHECK((a0 == box.min.x || a0 == row_start(field)) &&
                    (a1 == box.max.x || box.max.x >= field.interior().max.x),
                "Dma::put_box: box must start and end on 128-byte lines (TilePlan's x cuts)");
  const std::size_t bytes = std::size_t(a1 - a0) * sizeof(float);
  const bool streaming = field.raw_size() * sizeof(float) >= kStreamingPutFieldBytes;
  for (int y = box.min.y; y < box.max.y; ++y) {
    enqueue(field.row(y) + a0, local.row(y) + a0, bytes, tag, "put", streaming);
    bytes_out_ += bytes;
  }
}

}  // namespace ardcell
