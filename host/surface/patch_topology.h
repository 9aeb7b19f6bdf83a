#pragma once
// Patches of an all-quad control mesh, their adjacency and the transitions between their
// parametrisations (seed 004, Sec. 2 "transition functions", Fig. 4; Stam 2003).
//
// Patch p is face p over [0,1]^2: Bfr's parametrisation puts face vertex k at corner k of
// (0,0), (1,0), (1,1), (0,1). Edge k runs from corner k to corner k+1, counterclockwise as in
// the seed: 0 bottom (x2 = 0), 1 right (x1 = 1), 2 top (x2 = 1), 3 left (x1 = 0).
//
// The transition across edge e of p into its neighbour q (which meets it along its edge f) is
// derived here, not taken from the seed's prose: write a point of p's extended plane in the
// frame of edge e, x = c_e + s d_e + n o_e (start corner c_e, direction d_e, outward normal
// o_e). In q the shared edge runs the other way and p's outside is q's inside, so the same
// point is x' = c_f + (1 - s) d_f - n o_f, that is
//
//   x' = R x + t,   R = -(d_f d_e^T + o_f o_e^T),   t = c_f + d_f - R c_e.
//
// R is a rotation by a multiple of 90 degrees (both frames have determinant -1) and t is
// integer, so cell centres map onto cell centres. R is the Jacobian of the transition: a
// contravariant vector maps as v' = R v, the metric as g' = R g R^T (R^-T = R), the inverse
// metric the same way. The seed's point map phi_<e_i,e_j> o T_e_i is this map; its Jacobian
// is a rotation by -<e_i,e_j> quarter turns, not the printed "M_i = R_{i pi/2},
// counterclockwise" (tests/host/surface/patch_topology_test.cpp checks both, the round trip and
// the metric continuity).
#include <array>
#include <vector>

#include "host/config/status.h"
#include "host/surface/poly_mesh.h"

namespace ardcell {

// x' = R x + t with R the rotation by `quarter_turns` * 90 degrees counterclockwise.
struct EdgeTransition {
  int patch = -1;  // neighbour patch, -1 on a boundary edge
  int edge = -1;   // its edge
  int quarter_turns = 0;
  std::array<int, 2> t{0, 0};

  std::array<int, 4> rotation() const;  // R row-major (r00, r01, r10, r11)
  std::array<double, 2> map_point(std::array<double, 2> x) const;
  std::array<double, 2> map_vector(std::array<double, 2> v) const;
  // A symmetric tensor (a11, a12, a22) as R a R^T: the metric and the inverse metric.
  std::array<double, 3> map_tensor(std::array<double, 3> a) const;
};

// Position m (counted along the x1 or x2 axis) of edge e on a grid whose indices run from `lo`
// to `hi`: the outside index (lo or hi) and the one just inside it.
struct EdgeRingCell {
  int out_i, out_j, in_i, in_j;
};
EdgeRingCell edge_ring_cell(int e, int m, int lo, int hi);

// The transition across edge e of a patch into the neighbour meeting it along edge f.
EdgeTransition make_transition(int neighbour, int e, int f);

struct PatchTopology {
  int patches = 0;
  std::vector<EdgeTransition> across;             // [4 p + e]
  std::vector<std::array<int, 4>> corner_vertex;  // control vertex at each corner
  std::vector<int> valence;                       // faces around each control vertex
  std::vector<bool> boundary_vertex;

  const EdgeTransition& transition(int p, int e) const { return across[4 * p + e]; }
  // A corner whose vertex is interior with four faces: its diagonal neighbour is a patch.
  bool regular_corner(int p, int k) const {
    const int v = corner_vertex[p][k];
    return valence[v] == 4 && !boundary_vertex[v];
  }
};

// The connected piece of each patch (across shared edges), numbered 0, 1, ... in the order of
// each piece's first patch.
std::vector<int> patch_pieces(const PatchTopology& topo);

// Adjacency of an all-quad mesh that passed check_manifold; an error for a non-quad face.
Status build_patch_topology(const PolyMesh& quads, PatchTopology& out);

// Where the point x of patch p's extended plane lies: crossing at most two edges (a point
// beyond a corner needs two), it returns the patch whose closed unit square holds it and its
// coordinates there, with the quarter turns accumulated on the way (for vectors); -1 when the
// walk leaves the surface. Beyond a corner the answer is the diagonal patch only where the
// corner is regular (valence 4): around an extraordinary vertex the quadrant beyond the corner
// is not part of the surface and the walk lands in some other patch.
struct PatchPoint {
  int patch = -1;
  std::array<double, 2> x{0, 0};
  int quarter_turns = 0;
};
PatchPoint locate(const PatchTopology& topo, int p, std::array<double, 2> x);

}  // namespace ardcell
