#pragma once
// The Catmull-Clark limit surface of a control mesh, evaluated by OpenSubdiv (Bfr, 3.5): each
// quad face is a patch X_p : [0,1]^2 -> R^3 (seed 004, Sec. 3), with position and first and
// second derivatives at any (x1, x2). Meshes that are not all quads are refined once (Far);
// the limit surface is the same, and every face of the refined mesh is a quad.
//
// Near an extraordinary vertex Bfr represents the limit surface by patches of a refined
// neighbourhood, irregular ones as Gregory patches (SurfaceFactory::Options' smooth
// approximation level, here `approx_level`); they meet their neighbours with continuous position
// and tangent plane, not with a continuous parametric derivative: the metric continuity test
// reports how large the difference is and how fast it shrinks away from the vertex.
#include <array>
#include <memory>

#include "host/config/status.h"
#include "host/surface/patch_topology.h"
#include "host/surface/poly_mesh.h"

namespace ardcell {

struct LimitSample {
  std::array<double, 3> p, du, dv, duu, duv, dvv;
};

struct LimitSurfaceOptions {
  int approx_level = 6;  // Bfr's smooth approximation level near extraordinary vertices (1-10)
};

class LimitSurface {
 public:
  LimitSurface();
  ~LimitSurface();
  LimitSurface(LimitSurface&&) noexcept;
  LimitSurface& operator=(LimitSurface&&) noexcept;

  // Checks the mesh (check_manifold), refines it once when a face is not a quad, and prepares
  // every patch for evaluation. One line on failure.
  static Status build(PolyMesh mesh, const LimitSurfaceOptions& options, LimitSurface& out);

  int patches() const { return topology_.patches; }
  bool refined() const { return refined_; }
  const PolyMesh& quads() const { return quads_; }
  const PatchTopology& topology() const { return topology_; }
  // X_p and its derivatives at (x1, x2) in [0,1]^2.
  void evaluate(int patch, double x1, double x2, LimitSample& out) const;
  std::array<double, 3> position(int patch, double x1, double x2) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  PolyMesh quads_;
  PatchTopology topology_;
  bool refined_ = false;
};

// Position and unit normal of patch p's limit surface at (u, v) (the PLY, the OBJ and the
// renders share it).
void limit_vertex(const LimitSurface& surface, int p, double u, double v, double position[3],
                  double normal[3]);

// One uniform Catmull-Clark refinement (OpenSubdiv Far): every face of the result is a quad.
PolyMesh refine_catmull_clark_once(const PolyMesh& mesh);

}  // namespace ardcell
