#include "host/surface/limit_surface.h"

#include <cmath>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <vector>

namespace ardcell {

namespace osd = OpenSubdiv::OPENSUBDIV_VERSION;

namespace {

using Descriptor = osd::Far::TopologyDescriptor;

std::unique_ptr<osd::Far::TopologyRefiner> make_refiner(const PolyMesh& mesh,
                                                        std::vector<int>& sizes) {
  sizes.resize(mesh.face_count());
  for (int f = 0; f < mesh.face_count(); ++f) sizes[f] = mesh.face_size(f);
  Descriptor desc;
  desc.numVertices = int(mesh.points.size());
  desc.numFaces = mesh.face_count();
  desc.numVertsPerFace = sizes.data();
  desc.vertIndicesPerFace = mesh.face_vertices.data();
  osd::Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(osd::Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  using Factory = osd::Far::TopologyRefinerFactory<Descriptor>;
  return std::unique_ptr<osd::Far::TopologyRefiner>(
      Factory::Create(desc, Factory::Options(osd::Sdc::SCHEME_CATMARK, sdc)));
}

// The interface Far::PrimvarRefiner interpolates through.
struct Point3 {
  double x[3];
  void Clear() { x[0] = x[1] = x[2] = 0; }
  void AddWithWeight(const Point3& s, double w) {
    for (int k = 0; k < 3; ++k) x[k] += w * s.x[k];
  }
};

}  // namespace

struct LimitSurface::Impl {
  std::vector<int> face_sizes;
  std::unique_ptr<osd::Far::TopologyRefiner> refiner;
  std::vector<osd::Bfr::Surface<double>> surfaces;
  std::vector<std::vector<double>> patch_points;
};

LimitSurface::LimitSurface() = default;
LimitSurface::~LimitSurface() = default;
LimitSurface::LimitSurface(LimitSurface&&) noexcept = default;
LimitSurface& LimitSurface::operator=(LimitSurface&&) noexcept = default;

PolyMesh refine_catmull_clark_once(const PolyMesh& mesh) {
  std::vector<int> sizes;
  auto refiner = make_refiner(mesh, sizes);
  refiner->RefineUniform(osd::Far::TopologyRefiner::UniformOptions(1));
  const auto& level = refiner->GetLevel(1);
  std::vector<Point3> src(mesh.points.size()), dst(level.GetNumVertices());
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    for (int k = 0; k < 3; ++k) src[v].x[k] = mesh.points[v][k];
  const Point3* from = src.data();
  Point3* to = dst.data();
  osd::Far::PrimvarRefinerReal<double>(*refiner).Interpolate(1, from, to);
  PolyMesh out;
  out.points.resize(dst.size());
  for (std::size_t v = 0; v < dst.size(); ++v)
    out.points[v] = {dst[v].x[0], dst[v].x[1], dst[v].x[2]};
  for (int f = 0; f < level.GetNumFaces(); ++f) {
    const auto fv = level.GetFaceVertices(f);
    for (int k = 0; k < fv.size(); ++k) out.face_vertices.push_back(fv[k]);
    out.face_offsets.push_back(int(out.face_vertices.size()));
  }
  return out;
}

Status LimitSurface::build(PolyMesh mesh, const LimitSurfaceOptions& options, LimitSurface& out) {
  out = LimitSurface{};
  if (options.approx_level < 1 || options.approx_level > 10)
    return Status::error("approximation level " + std::to_string(options.approx_level) +
                         " is outside 1..10");
  if (Status s = check_manifold(mesh); !s) return s;
  drop_unused_points(mesh);
  if (!mesh.all_quads()) {
    mesh = refine_catmull_clark_once(mesh);
    out.refined_ = true;
  }
  if (Status s = build_patch_topology(mesh, out.topology_); !s) return s;
  out.quads_ = std::move(mesh);
  out.impl_ = std::make_unique<Impl>();
  Impl& im = *out.impl_;
  im.refiner = make_refiner(out.quads_, im.face_sizes);
  if (!im.refiner) return Status::error("OpenSubdiv did not accept the mesh");
  osd::Bfr::RefinerSurfaceFactory<>::Options fopt;
  fopt.SetApproxLevelSmooth(options.approx_level);
  const osd::Bfr::RefinerSurfaceFactory<> factory(*im.refiner, fopt);
  const int patches = out.topology_.patches;
  im.surfaces.resize(patches);
  im.patch_points.resize(patches);
  const double* mesh_points = out.quads_.points.front().data();
  for (int p = 0; p < patches; ++p) {
    auto& surface = im.surfaces[p];
    if (!factory.InitVertexSurface<double>(p, &surface) || !surface.IsValid())
      return Status::error("OpenSubdiv has no limit surface for face " + std::to_string(p + 1));
    im.patch_points[p].resize(std::size_t(surface.GetNumPatchPoints()) * 3);
    surface.PreparePatchPoints(mesh_points, 3, im.patch_points[p].data(), 3);
  }
  return Status::ok();
}

void LimitSurface::evaluate(int patch, double x1, double x2, LimitSample& out) const {
  const double uv[2] = {x1, x2};
  impl_->surfaces[patch].Evaluate(uv, impl_->patch_points[patch].data(), 3, out.p.data(),
                                  out.du.data(), out.dv.data(), out.duu.data(), out.duv.data(),
                                  out.dvv.data());
}

std::array<double, 3> LimitSurface::position(int patch, double x1, double x2) const {
  const double uv[2] = {x1, x2};
  std::array<double, 3> p;
  impl_->surfaces[patch].Evaluate(uv, impl_->patch_points[patch].data(), 3, p.data());
  return p;
}

void limit_vertex(const LimitSurface& surface, int p, double u, double v, double position[3],
                  double normal[3]) {
  LimitSample d;
  surface.evaluate(p, u, v, d);
  double nx = d.du[1] * d.dv[2] - d.du[2] * d.dv[1];
  double ny = d.du[2] * d.dv[0] - d.du[0] * d.dv[2];
  double nz = d.du[0] * d.dv[1] - d.du[1] * d.dv[0];
  const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
  if (len > 0) nx /= len, ny /= len, nz /= len;
  for (int k = 0; k < 3; ++k) position[k] = d.p[std::size_t(k)];
  normal[0] = nx, normal[1] = ny, normal[2] = nz;
}

}  // namespace ardcell
