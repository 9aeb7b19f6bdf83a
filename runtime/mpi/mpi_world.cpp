#include "runtime/mpi/mpi_world.h"

#include <climits>

// The C API only (Open MPI's mpi.h otherwise declares its deprecated C++ bindings).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstring>

#include "runtime/check.h"

namespace ardcell {
namespace {

// One message tag for every exchange and gather: messages between two ranks do not overtake
// each other, and every rank issues them in the same order.
constexpr int kTag = 7;

long long elapsed_ns(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() -
                                                              start)
      .count();
}

std::size_t cells(const std::vector<HaloCopy>& boxes) {
  std::size_t n = 0;
  for (const HaloCopy& c : boxes) n += std::size_t(c.box.area());
  return n;
}

// Rows of `box` (read at box + shift) into `out`, row after row; returns the next free float.
float* pack(const FieldF& f, const Box2& box, Int2 shift, float* out) {
  for (int y = box.min.y; y < box.max.y; ++y) {
    std::memcpy(out, f.row(y + shift.y) + box.min.x + shift.x,
                std::size_t(box.width()) * sizeof(float));
    out += box.width();
  }
  return out;
}

const float* unpack(const float* in, const Box2& box, FieldF& f) {
  for (int y = box.min.y; y < box.max.y; ++y) {
    std::memcpy(f.row(y) + box.min.x, in, std::size_t(box.width()) * sizeof(float));
    in += box.width();
  }
  return in;
}

}  // namespace

MpiWorld::MpiWorld() {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiWorld::~MpiWorld() { MPI_Finalize(); }

bool MpiWorld::any(bool flag) const {
  int local = flag ? 1 : 0, all = 0;
  MPI_Allreduce(&local, &all, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
  return all != 0;
}

double MpiWorld::sum(double value) const {
  double all = 0;
  MPI_Allreduce(&value, &all, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return all;
}

void MpiWorld::min_max(float& lo, float& hi) const {
  float in[2] = {-lo, hi}, out[2] = {0, 0};
  MPI_Allreduce(in, out, 2, MPI_FLOAT, MPI_MAX, MPI_COMM_WORLD);
  lo = -out[0];
  hi = out[1];
}

void MpiWorld::barrier() const { MPI_Barrier(MPI_COMM_WORLD); }

void MpiWorld::all_gather(const void* mine, std::size_t bytes, void* all) const {
  ARDCELL_CHECK(bytes <= std::size_t(INT_MAX), "MpiWorld::all_gather: too many bytes");
  MPI_Allgather(mine, int(bytes), MPI_BYTE, all, int(bytes), MPI_BYTE, MPI_COMM_WORLD);
}

void MpiWorld::broadcast(void* data, std::size_t bytes) const {
  // In pieces of at most INT_MAX bytes (MPI counts are ints).
  auto* at = static_cast<unsigned char*>(data);
  for (std::size_t done = 0; done < bytes;) {
    const std::size_t n = std::min<std::size_t>(bytes - done, std::size_t(INT_MAX));
    MPI_Bcast(at + done, int(n), MPI_BYTE, 0, MPI_COMM_WORLD);
    done += n;
  }
}

void MpiWorld::gather_to_root(std::span<const unsigned char> mine, std::vector<unsigned char>& all,
                              std::vector<int>& counts) const {
  ARDCELL_CHECK(mine.size() <= std::size_t(INT_MAX), "MpiWorld::gather_to_root: too many bytes");
  const int count = int(mine.size());
  counts.assign(std::size_t(size_), 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<int> offsets(std::size_t(size_), 0);
  if (rank_ == 0) {
    long long total = 0;
    for (int r = 0; r < size_; ++r) {
      offsets[std::size_t(r)] = int(total);
      total += counts[std::size_t(r)];
    }
    ARDCELL_CHECK(total <= INT_MAX, "MpiWorld::gather_to_root: too many bytes");
    all.resize(std::size_t(total));
  }
  MPI_Gatherv(mine.data(), count, MPI_BYTE, rank_ == 0 ? all.data() : nullptr, counts.data(),
              offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
}

// The requests of the exchange in flight: at most 8 neighbours and their images.
struct MpiHaloChannel::Requests {
  static constexpr int kMax = 64;
  MPI_Request request[kMax];
  int count = 0;
};

MpiHaloChannel::MpiHaloChannel(const BlockLayout& layout, int width, const MpiWorld& world)
    : block_(world.rank()),
      exchange_(layout, width),
      sums_(kMaxSums * std::size_t(layout.count())) {
  ARDCELL_CHECK(world.size() == layout.count(), "MpiHaloChannel: one rank per block");
  const auto peer = [&](int rank) -> Peer& {
    for (Peer& p : peers_)
      if (p.rank == rank) return p;
    peers_.push_back(Peer{rank, {}, {}, 0, 0, {}, {}});
    return peers_.back();
  };
  // What this block receives, and what every other block receives from it: the same boxes
  // in the same order on both sides.
  for (const HaloCopy& c : exchange_.copies_into(block_)) {
    if (c.src_block == block_)
      self_.push_back(c);
    else
      peer(c.src_block).recv.push_back(c);
  }
  for (int b = 0; b < layout.count(); ++b)
    if (b != block_)
      for (const HaloCopy& c : exchange_.copies_into(b))
        if (c.src_block == block_) peer(b).send.push_back(c);
  std::sort(peers_.begin(), peers_.end(),
            [](const Peer& a, const Peer& b) { return a.rank < b.rank; });
  for (Peer& p : peers_) {
    p.recv_buf.resize(cells(p.recv));
    p.send_buf.resize(cells(p.send));
  }
  fields_.reserve(kMaxFields);
  requests_ = std::make_unique<Requests>();
}

// An owner unwinding between begin and finish: the messages still land in the buffers.
MpiHaloChannel::~MpiHaloChannel() {
  if (requests_ && requests_->count > 0)
    MPI_Waitall(requests_->count, requests_->request, MPI_STATUSES_IGNORE);
}

void MpiHaloChannel::begin(std::span<const HaloField> fields) {
  const auto start = std::chrono::steady_clock::now();
  ARDCELL_CHECK(requests_->count == 0 && fields_.empty(),
                "MpiHaloChannel: begin while an exchange is in flight");
  ARDCELL_CHECK(fields.size() <= fields_.capacity(), "MpiHaloChannel: too many fields at once");
  ARDCELL_CHECK(2 * peers_.size() <= std::size_t(Requests::kMax),
                "MpiHaloChannel: too many neighbours");
  for (const HaloField& f : fields) {
    ARDCELL_CHECK(f.field->halo() >= exchange_.width(),
                  "MpiHaloChannel: a field's halo is narrower than the exchange");
    ARDCELL_CHECK(f.depth >= 0 && f.depth <= exchange_.width(),
                  "MpiHaloChannel: depth beyond the exchange's width");
    fields_.push_back(f);
  }
  // One message each way per neighbour: every field's boxes, field after field, both sides
  // cutting the same boxes to the receiving block grown by the field's depth.
  for (Peer& p : peers_) {
    p.recv_count = p.send_count = 0;
    for (const HaloField& f : fields) {
      for (const HaloCopy& c : p.recv)
        p.recv_count += std::size_t(exchange_.within(c, block_, f.depth).area());
      for (const HaloCopy& c : p.send)
        p.send_count += std::size_t(exchange_.within(c, p.rank, f.depth).area());
    }
    // Sized for one field at full width on construction; a step of several fields grows them
    // in the first frame, never after.
    if (p.recv_buf.size() < p.recv_count) p.recv_buf.resize(p.recv_count);
    if (p.send_buf.size() < p.send_count) p.send_buf.resize(p.send_count);
  }
  Requests& r = *requests_;
  for (Peer& p : peers_)
    if (p.recv_count > 0)
      MPI_Irecv(p.recv_buf.data(), int(p.recv_count), MPI_FLOAT, p.rank, kTag, MPI_COMM_WORLD,
                &r.request[r.count++]);
  for (Peer& p : peers_) {
    if (p.send_count == 0) continue;
    float* out = p.send_buf.data();
    for (const HaloField& f : fields)
      for (const HaloCopy& c : p.send)
        out = pack(*f.field, exchange_.within(c, p.rank, f.depth), c.shift, out);
    MPI_Isend(p.send_buf.data(), int(p.send_count), MPI_FLOAT, p.rank, kTag, MPI_COMM_WORLD,
              &r.request[r.count++]);
    bytes_sent_ += double(p.send_count * sizeof(float));
  }
  for (const HaloField& f : fields)
    for (const HaloCopy& c : self_)
      copy_halo_cells(*f.field, c, exchange_.within(c, block_, f.depth), *f.field);
  ns_ += elapsed_ns(start);
}

void MpiHaloChannel::progress() {
  const auto start = std::chrono::steady_clock::now();
  Requests& r = *requests_;
  int done = 0;
  if (r.count > 0) MPI_Testall(r.count, r.request, &done, MPI_STATUSES_IGNORE);
  ns_ += elapsed_ns(start);
}

void MpiHaloChannel::finish() {
  const auto start = std::chrono::steady_clock::now();
  Requests& r = *requests_;
  MPI_Waitall(r.count, r.request, MPI_STATUSES_IGNORE);
  r.count = 0;
  for (Peer& p : peers_) {
    if (p.recv_count == 0) continue;
    const float* in = p.recv_buf.data();
    for (const HaloField& f : fields_)
      for (const HaloCopy& c : p.recv)
        in = unpack(in, exchange_.within(c, block_, f.depth), *f.field);
  }
  fields_.clear();
  ns_ += elapsed_ns(start);
}

void MpiHaloChannel::gather_all(const FieldF& field, FieldF& whole) {
  const auto start = std::chrono::steady_clock::now();
  ARDCELL_CHECK(requests_->count == 0, "MpiHaloChannel: gather_all while an exchange is in flight");
  if (gather_counts_.empty()) {  // the first gather: MPI's counts are ints
    long long total = 0;
    for (int b = 0; b < exchange_.count(); ++b) {
      gather_offsets_.push_back(int(std::min<long long>(total, INT_MAX)));
      gather_counts_.push_back(int(exchange_.owned(b).area()));
      total += exchange_.owned(b).area();
    }
    ARDCELL_CHECK(total <= INT_MAX, "MpiHaloChannel: a grid too large to gather");
    gathered_.resize(std::size_t(total));
  }
  const std::size_t mine = std::size_t(block_);
  pack(field, exchange_.owned(block_), Int2{0, 0}, gathered_.data() + gather_offsets_[mine]);
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, gathered_.data(), gather_counts_.data(),
                 gather_offsets_.data(), MPI_FLOAT, MPI_COMM_WORLD);
  for (int b = 0; b < exchange_.count(); ++b)
    unpack(gathered_.data() + gather_offsets_[std::size_t(b)], exchange_.owned(b), whole);
  bytes_sent_ +=
      double(std::size_t(gather_counts_[mine]) * sizeof(float)) * double(exchange_.count() - 1);
  ns_ += elapsed_ns(start);
}

void MpiHaloChannel::sum(std::span<double> values) {
  const auto start = std::chrono::steady_clock::now();
  ARDCELL_CHECK(requests_->count == 0 && values.size() <= kMaxSums,
                "MpiHaloChannel: a sum of at most kMaxSums values, with no exchange in flight");
  const std::size_t n = values.size();
  MPI_Allgather(values.data(), int(n), MPI_DOUBLE, sums_.data(), int(n), MPI_DOUBLE,
                MPI_COMM_WORLD);
  for (std::size_t i = 0; i < n; ++i) {
    double total = 0.0;
    for (int r = 0; r < exchange_.count(); ++r) total += sums_[std::size_t(r) * n + i];
    values[i] = total;
  }
  bytes_sent_ += double(n * sizeof(double)) * double(exchange_.count() - 1);
  ns_ += elapsed_ns(start);
}

BlockGather::BlockGather(const BlockLayout& layout, const MpiWorld& world)
    : layout_(layout), rank_(world.rank()) {
  std::size_t most = 0;
  for (int b = 0; b < layout.count(); ++b)
    most = std::max(most, std::size_t(layout.owned(b).area()));
  buffer_.resize(most);
}

void BlockGather::gather(const FieldF& block, FieldF* whole) {
  if (rank_ != 0) {
    pack(block, layout_.owned(rank_), Int2{0, 0}, buffer_.data());
    MPI_Send(buffer_.data(), int(layout_.owned(rank_).area()), MPI_FLOAT, 0, kTag, MPI_COMM_WORLD);
    return;
  }
  ARDCELL_CHECK(whole && whole->interior() == box_of_size(layout_.domain()) && whole->halo() >= 1,
                "BlockGather: rank 0 gathers into a field of the whole grid");
  copy_box<float>(block.view(), whole->view(), layout_.owned(0));
  for (int r = 1; r < layout_.count(); ++r) {
    const Box2 box = layout_.owned(r);
    MPI_Recv(buffer_.data(), int(box.area()), MPI_FLOAT, r, kTag, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    unpack(buffer_.data(), box, *whole);
  }
}

}  // namespace ardcell
