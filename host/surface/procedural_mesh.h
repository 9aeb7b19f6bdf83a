#pragma once
// Control meshes built in code, so that surfaces run and test without a file.
#include <cstdint>

#include "host/surface/poly_mesh.h"

namespace ardcell {

// The cube [-1, 1]^3 with each face cut into k x k quads, outward-facing. Its Catmull-Clark
// limit is the "cube-sphere": 8 extraordinary vertices of valence 3.
PolyMesh cube_mesh(int k);

// A box of nx x ny x nz unit cells, each side cut into its cells' quads (2 (nx ny + ny nz + nz nx)
// patches), centred, its longest side 2, outward-facing; box_mesh(k, k, k) is cube_mesh(k).
PolyMesh box_mesh(int nx, int ny, int nz);

// A torus of `around` x `tube` quads (major radius R, minor r): every vertex has valence 4.
PolyMesh torus_mesh(int around, int tube, double R, double r);

// A closed surface of genus 2: the outside of a 5 x 3 x 1 plate of unit cubes with the cubes at
// (1, 1) and (3, 1) taken out, centred on the origin and scaled by `size` (50 quads,
// outward-facing). Its Catmull-Clark limit is a smooth double torus.
PolyMesh genus2_mesh(double size);

// The same faces, each with its vertex list rotated by a pseudo-random 0-3 places, so that the
// patches' parametrisations meet with every quarter turn.
PolyMesh rotate_faces(const PolyMesh& mesh, std::uint32_t seed);

}  // namespace ardcell
