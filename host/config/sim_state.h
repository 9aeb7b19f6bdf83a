#pragma once
// The whole state of a running simulation: what `--save-state` writes and loading resumes.
// All fields are cell-centred (Stam's collocated grid), size.x by size.y cells, halo 1.
#include <cstdint>
#include <string_view>
#include <utility>

#include "runtime/field.h"

namespace ardcell {

struct SimState {
  Int2 size;
  double h = 0;  // cell size; the domain is size * h
  double dt = 0;
  double time = 0;     // the scene's time: frames x dt
  double rd_time = 0;  // the RD's own time: rd.dt x rd.steps_per_frame per frame (0: no RD)
  int64_t step = 0;

  FieldF u, v, p, dye;      // fluid: velocity, pressure, passive dye
  FieldF A, B, theta0;      // reaction-diffusion chemicals and per-cell anisotropy angle
  Field<uint8_t> obstacle;  // 1 = solid cell (flow past obstacles); empty when none

  // Calls f(name, field) for each float field that is allocated, in a fixed order; the names
  // are those of the saved .npy files (u, v, p, dye, A, B, theta0).
  template <class F>
  void for_each_field(F&& f) {
    visit_fields(*this, f);
  }
  template <class F>
  void for_each_field(F&& f) const {
    visit_fields(*this, f);
  }
  // The float field of that name (allocated or not); nullptr for an unknown name.
  FieldF* field(std::string_view name) {
    for (auto [n, f] : {std::pair<std::string_view, FieldF*>{"u", &u},
                        {"v", &v},
                        {"p", &p},
                        {"dye", &dye},
                        {"A", &A},
                        {"B", &B},
                        {"theta0", &theta0}})
      if (n == name) return f;
    return nullptr;
  }

 private:
  template <class Self, class F>
  static void visit_fields(Self& s, F& f) {
    if (!s.u.empty()) f(std::string_view("u"), s.u);
    if (!s.v.empty()) f(std::string_view("v"), s.v);
    if (!s.p.empty()) f(std::string_view("p"), s.p);
    if (!s.dye.empty()) f(std::string_view("dye"), s.dye);
    if (!s.A.empty()) f(std::string_view("A"), s.A);
    if (!s.B.empty()) f(std::string_view("B"), s.B);
    if (!s.theta0.empty()) f(std::string_view("theta0"), s.theta0);
  }
};

}  // namespace ardcell
