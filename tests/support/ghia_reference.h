#pragma once
// Ghia, Ghia & Shin (1982), Tables I and II (../shared/refdata/ghia/): the lid-driven cavity's u
// on the vertical centre line and v on the horizontal one, and how to sample ardcell's fields at
// their points. Shared by tests/host/engine/ghia_test.cpp and bench/ghia_bench.cpp.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "runtime/field.h"

namespace ardcell::ghia {

struct Point {
  double position;  // y for Table I (u on x = 0.5), x for Table II (v on y = 0.5)
  double value;
};

// The Reynolds numbers of the tables' columns, in order.
inline constexpr int kReynolds[] = {100, 400, 1000, 3200, 5000, 7500, 10000};

// Table I ("y u100 u400 ...") or Table II ("gridpoint x v100 ...") at Reynolds number re (one of
// kReynolds); '#' and '-' lines are comments. Empty when the file or the column is missing.
inline std::vector<Point> read(bool table_two, int re) {
  const std::string file = table_two ? "ghia1982_tableII_v_horizontal_centerline.txt"
                                     : "ghia1982_tableI_u_vertical_centerline.txt";
  const int position_column = table_two ? 1 : 0;
  const auto* it = std::find(std::begin(kReynolds), std::end(kReynolds), re);
  if (it == std::end(kReynolds)) return {};
  const int value_column = position_column + 1 + int(it - std::begin(kReynolds));
  std::ifstream in(std::string(ARDCELL_SHARED_DIR) + "/refdata/ghia/" + file);
  std::vector<Point> points;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::vector<double> numbers;
    double value;
    while (row >> value) numbers.push_back(value);
    if (line.empty() || line[0] == '#' || numbers.size() <= std::size_t(value_column)) continue;
    points.push_back({numbers[std::size_t(position_column)], numbers[std::size_t(value_column)]});
  }
  return points;
}

// Bilinear interpolation of a cell-centred field at a point (domain units, cell size h), with
// the ghost cells (filled by the boundary rules) giving the wall values.
inline double sample(const FieldF& f, double h, double x, double y) {
  const double gx = x / h - 0.5, gy = y / h - 0.5;  // cell (i, j) is centred at ((i+.5)h, (j+.5)h)
  const int i0 = std::min(std::max(int(std::floor(gx)), -1), f.nx() - 1);
  const int j0 = std::min(std::max(int(std::floor(gy)), -1), f.ny() - 1);
  const double s = gx - i0, t = gy - j0;
  return (1 - t) * ((1 - s) * f(i0, j0) + s * f(i0 + 1, j0)) +
         t * ((1 - s) * f(i0, j0 + 1) + s * f(i0 + 1, j0 + 1));
}

// The largest |ours - Ghia| over Table I's points (u) and Table II's (v).
struct Errors {
  double u = 0.0, v = 0.0;
};
inline Errors max_errors(const FieldF& u, const FieldF& v, double h, int re) {
  Errors e;
  for (const Point& p : read(false, re))
    e.u = std::max(e.u, std::abs(sample(u, h, 0.5, p.position) - p.value));
  for (const Point& p : read(true, re))
    e.v = std::max(e.v, std::abs(sample(v, h, p.position, 0.5) - p.value));
  return e;
}

}  // namespace ardcell::ghia
