#include "runtime/block_layout.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <stdexcept>

#include "runtime/check.h"

namespace ardcell {
namespace {

// Cut points of n cells into k parts, the first n % k one cell larger.
std::vector<int> cuts(int n, int k) {
  std::vector<int> at{0};
  for (int i = 0; i < k; ++i) at.push_back(at.back() + n / k + (i < n % k ? 1 : 0));
  return at;
}

}  // namespace

BlockLayout BlockLayout::split(Int2 domain, Int2 parts, bool periodic_x, bool periodic_y) {
  if (parts.x < 1 || parts.y < 1 || parts.x > domain.x || parts.y > domain.y) {
    char why[160];
    std::snprintf(why, sizeof why,
                  "blocks %dx%d: a %dx%d grid cuts into 1 to %d blocks along x and 1 to %d "
                  "along y",
                  parts.x, parts.y, domain.x, domain.y, domain.x, domain.y);
    throw std::invalid_argument(why);
  }
  BlockLayout l;
  l.domain_ = domain;
  l.parts_ = parts;
  l.periodic_x_ = periodic_x;
  l.periodic_y_ = periodic_y;
  const std::vector<int> xs = cuts(domain.x, parts.x), ys = cuts(domain.y, parts.y);
  for (int j = 0; j < parts.y; ++j)
    for (int i = 0; i < parts.x; ++i)
      l.blocks_.push_back(Box2{{xs[std::size_t(i)], ys[std::size_t(j)]},
                               {xs[std::size_t(i) + 1], ys[std::size_t(j) + 1]}});
  return l;
}

Box2 BlockLayout::owned(int b) const {
  Box2 o = block(b);
  if (!periodic_x_) {
    if (o.min.x == 0) o.min.x = -1;
    if (o.max.x == domain_.x) o.max.x = domain_.x + 1;
  }
  if (!periodic_y_) {
    if (o.min.y == 0) o.min.y = -1;
    if (o.max.y == domain_.y) o.max.y = domain_.y + 1;
  }
  return o;
}

bool parse_block_parts(std::string_view text, Int2& out) {
  const std::size_t x = text.find('x');
  if (x == std::string_view::npos) return false;
  const auto number = [](std::string_view s, int& v) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size() && v >= 1;
  };
  Int2 p;
  if (!number(text.substr(0, x), p.x) || !number(text.substr(x + 1), p.y)) return false;
  out = p;
  return true;
}

HaloExchange::HaloExchange(const BlockLayout& layout, int width)
    : width_(width), periodic_x_(layout.periodic_x()), periodic_y_(layout.periodic_y()) {
  const Int2 d = layout.domain();
  ARDCELL_CHECK(width >= 0, "HaloExchange: negative width");
  ARDCELL_CHECK((!layout.periodic_x() || width <= d.x) && (!layout.periodic_y() || width <= d.y),
                "HaloExchange: the halo is wider than the periodic domain");
  // Images of the domain a halo can reach: itself, and one width away along a periodic axis.
  const int sx = layout.periodic_x() ? 1 : 0, sy = layout.periodic_y() ? 1 : 0;
  for (int b = 0; b < layout.count(); ++b) {
    blocks_.push_back(layout.block(b));
    owned_.push_back(layout.owned(b));
  }
  for (int b = 0; b < layout.count(); ++b) {
    first_.push_back(copies_.size());
    const Box2 halo = layout.block(b).grown(width);
    for (int src = 0; src < layout.count(); ++src)
      for (int iy = -sy; iy <= sy; ++iy)
        for (int ix = -sx; ix <= sx; ++ix) {
          if (src == b && ix == 0 && iy == 0) continue;
          const Int2 image{ix * d.x, iy * d.y};
          const Box2 box = halo.intersected(layout.owned(src).shifted(image));
          if (!box.empty()) copies_.push_back(HaloCopy{src, box, Int2{0, 0} - image});
        }
  }
  first_.push_back(copies_.size());
}

std::span<const HaloCopy> HaloExchange::copies_into(int block) const {
  const std::size_t a = first_[std::size_t(block)], e = first_[std::size_t(block) + 1];
  return std::span<const HaloCopy>(copies_).subspan(a, e - a);
}

std::size_t HaloExchange::cells_into(int block) const {
  std::size_t n = 0;
  for (const HaloCopy& c : copies_into(block)) n += std::size_t(c.box.area());
  return n;
}

void HaloExchange::fill(std::span<FieldF* const> fields, int block, int depth) const {
  FieldF& dst = *fields[std::size_t(block)];
  ARDCELL_CHECK(dst.halo() >= width_, "HaloExchange: a field's halo is narrower than the exchange");
  ARDCELL_CHECK(depth >= 0 && depth <= width_, "HaloExchange: depth beyond the exchange's width");
  for (const HaloCopy& c : copies_into(block)) {
    copy_halo_cells(*fields[std::size_t(c.src_block)], c, within(c, block, depth), dst);
  }
}

void copy_halo_cells(const FieldF& src, const HaloCopy& copy, const Box2& box, FieldF& dst) {
  if (box.empty()) return;
  // src's cells at box + shift, addressed as box.
  const View<const float> from(src.view(box.shifted(copy.shift)).data(), src.stride(), box);
  copy_box<float>(from, dst.view(), box);
}

bool HaloExchange::fills_any(int block, const Box2& box) const {
  for (const HaloCopy& c : copies_into(block))
    if (!c.box.intersected(box).empty()) return true;
  return false;
}

LocalBlockGroup::LocalBlockGroup(const BlockLayout& layout, int width)
    : exchange_(layout, width),
      posted_(std::size_t(layout.count()), nullptr),
      sums_(std::size_t(layout.count())),
      barrier_(layout.count()) {
  for (int b = 0; b < layout.count(); ++b) channels_.emplace_back(this, b);
}

void LocalBlockGroup::Channel::begin(std::span<const HaloField> fields) {
  LocalBlockGroup& g = *group_;
  for (const HaloField& f : fields) {
    g.posted_[std::size_t(block_)] = f.field;
    g.barrier_.arrive_and_wait();  // every block's field is posted and its cells are final
    g.exchange_.fill(g.posted_, block_, f.depth);
    g.barrier_.arrive_and_wait();  // every halo is filled before anyone writes its cells again
  }
}

void LocalBlockGroup::Channel::gather_all(const FieldF& field, FieldF& whole) {
  LocalBlockGroup& g = *group_;
  const HaloExchange& e = g.exchange_;
  // Read only, like every block's cells while the others copy them.
  g.posted_[std::size_t(block_)] = const_cast<FieldF*>(&field);
  g.barrier_.arrive_and_wait();
  for (int b = 0; b < e.count(); ++b)
    copy_box<float>(g.posted_[std::size_t(b)]->view(), whole.view(), e.owned(b));
  g.barrier_.arrive_and_wait();  // no block writes its cells before every copy is made
}

void LocalBlockGroup::Channel::sum(std::span<double> values) {
  LocalBlockGroup& g = *group_;
  ARDCELL_CHECK(values.size() <= kMaxSums, "HaloChannel::sum: at most kMaxSums values");
  std::copy(values.begin(), values.end(), g.sums_[std::size_t(block_)].begin());
  g.barrier_.arrive_and_wait();  // every block's values are posted
  for (std::size_t i = 0; i < values.size(); ++i) {
    double total = 0.0;
    for (const auto& posted : g.sums_) total += posted[i];
    values[i] = total;
  }
  g.barrier_.arrive_and_wait();  // no block posts again before every block has read
}

}  // namespace ardcell
