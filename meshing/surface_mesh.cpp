#include "meshing/surface_mesh.h"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pipeline/error.h"
#include "scan2cad/fit.h"

namespace meshing {

namespace {

// gmsh's triangle quality "gamma" = 2 r / R (inscribed over circumscribed radius, 1 for an
// equilateral triangle). Computed here because gmsh 4.8's API has no getElementQualities.
double gamma(const std::size_t* tri) {
  double p[3][3];
  for (int k = 0; k < 3; ++k) {
    std::vector<double> xyz, uvw;
    gmsh::model::mesh::getNode(tri[k], xyz, uvw);
    for (int j = 0; j < 3; ++j) p[k][j] = xyz[j];
  }
  auto len = [&](int i, int j) {
    return std::sqrt((p[i][0] - p[j][0]) * (p[i][0] - p[j][0]) + (p[i][1] - p[j][1]) * (p[i][1] - p[j][1]) +
                     (p[i][2] - p[j][2]) * (p[i][2] - p[j][2]));
  };
  const double a = len(1, 2), b = len(0, 2), c = len(0, 1), s = (a + b + c) / 2;
  const double area2 = std::max(0.0, s * (s - a) * (s - b) * (s - c));  // Heron, squared area
  if (area2 <= 0) return 0;
  const double area = std::sqrt(area2), r = area / s, R = a * b * c / (4 * area);
  return 2 * r / R;
}

}  // namespace

std::vector<SurfaceMeshPart> surface_mesh(const pipeline::SurfaceMesh& fitted, const std::string& kind,
                                          double size_mm, double back_size_mm, double min_gamma) {
  const pipeline::SurfaceMesh mesh = scan2cad::remesh_parts(fitted, kind, size_mm, back_size_mm);
  const auto parts = scan2cad::build_part_model(mesh, kind, false);
  std::vector<SurfaceMeshPart> out;
  for (const auto& p : parts) {
    std::vector<std::size_t> tags, nodes;
    gmsh::model::mesh::getElementsByType(2, tags, nodes, p.surface_tag);
    std::vector<double> q;
    for (std::size_t e = 0; e < tags.size(); ++e) q.push_back(gamma(nodes.data() + 3 * e));
    SurfaceMeshPart s{p.name, tags.size(), 1.0, 0.0};
    for (double g : q) {
      s.min_gamma = std::min(s.min_gamma, g);
      s.mean_gamma += g / q.size();
    }
    if (s.min_gamma < min_gamma) {
      char msg[160];
      std::snprintf(msg, sizeof msg, "part %s has a triangle of quality gamma %.3f < %.2f", p.name.c_str(),
                    s.min_gamma, min_gamma);
      throw pipeline::algorithm_failed("surface_mesh", msg);
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace meshing
