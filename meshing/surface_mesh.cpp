#include "meshing/surface_mesh.h"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pipeline/error.h"
#include "scan2cad/fit.h"

namespace meshing {

namespace {

// gmsh's "gamma" of a triangle of the current model (gmsh 4.8's API has no getElementQualities).
double gamma(const std::size_t* tri) {
  pipeline::Point p[3];
  for (int k = 0; k < 3; ++k) {
    std::vector<double> xyz, uvw;
    gmsh::model::mesh::getNode(tri[k], xyz, uvw);
    p[k] = pipeline::Point(xyz[0], xyz[1], xyz[2]);
  }
  return scan2cad::triangle_gamma(p[0], p[1], p[2]);
}

}  // namespace

std::vector<SurfaceMeshPart> surface_mesh(const pipeline::SurfaceMesh& fitted, const std::string& kind,
                                          double size_mm, double back_size_mm, double min_gamma) {
  pipeline::SurfaceMesh mesh = scan2cad::remesh_parts(fitted, kind, size_mm, back_size_mm);
  // The remeshing leaves a few poor triangles where a cut turns or where the back pass collapsed
  // cut edges (gamma 0.25 on the unrepaired NIOSH medium); flips and angle smoothing lift them.
  scan2cad::improve_triangles(mesh);
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
