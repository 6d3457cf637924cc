#include "meshing/surface_mesh.h"

#include <gmsh.h>

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/centroid.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "pipeline/error.h"
#include "pipeline/require_affordable_edge.h"
#include "scan2cad/fit.h"

namespace meshing {

namespace {

// A triangle of the current gmsh model, by its three node tags.
std::array<pipeline::Point, 3> corners(const std::size_t* tri) {
  std::array<pipeline::Point, 3> p;
  for (int k = 0; k < 3; ++k) {
    std::vector<double> xyz, uvw;
    gmsh::model::mesh::getNode(tri[k], xyz, uvw);
    p[k] = pipeline::Point(xyz[0], xyz[1], xyz[2]);
  }
  return p;
}

// gmsh's "gamma" of a triangle of the current model (gmsh 4.8's API has no getElementQualities).
double gamma(const std::size_t* tri) {
  const auto p = corners(tri);
  return scan2cad::triangle_gamma(p[0], p[1], p[2]);
}

}  // namespace

double default_back_size_for(double size_mm) {
  return std::max(size_mm, std::min(default_back_size_mm, back_size_ratio * size_mm));
}

std::vector<SurfaceMeshPart> surface_mesh(const pipeline::SurfaceMesh& fitted, const std::string& kind,
                                          double size_mm, double back_size_mm, double min_gamma, int max_retries,
                                          SurfaceMeshRetries* retries, pipeline::Progress* progress, double max_triangles) {
  SurfaceMeshRetries tried;
  const double area_mm2 = CGAL::Polygon_mesh_processing::area(fitted);
  for (int attempt = 0;; ++attempt) {
    if (progress)
      progress->step("meshing at size " + pipeline::format_number(size_mm) + " mm" +
                     (kind == "head" ? ", back " + pipeline::format_number(back_size_mm) + " mm" : std::string()));
    pipeline::SurfaceMesh mesh = scan2cad::remesh_parts(fitted, kind, size_mm, back_size_mm);
    // The remeshing leaves a few poor triangles where a cut turns or where the back pass collapsed
    // cut edges (gamma 0.25 on the unrepaired NIOSH medium); flips and angle smoothing lift them.
    scan2cad::improve_triangles(mesh);
    const auto parts = scan2cad::build_part_model(mesh, kind, false);
    std::vector<SurfaceMeshPart> out;
    std::string failure;
    for (const auto& p : parts) {
      std::vector<std::size_t> tags, nodes;
      gmsh::model::mesh::getElementsByType(2, tags, nodes, p.surface_tag);
      SurfaceMeshPart s{p.name, tags.size(), 1.0, 0.0};
      std::size_t worst = 0;
      for (std::size_t e = 0; e < tags.size(); ++e) {
        const double g = gamma(nodes.data() + 3 * e);
        if (g < s.min_gamma) s.min_gamma = g, worst = e;
        s.mean_gamma += g / double(tags.size());
      }
      if (s.min_gamma < min_gamma && failure.empty()) {
        const auto c = corners(nodes.data() + 3 * worst);
        const pipeline::Point centre = CGAL::centroid(c[0], c[1], c[2]);
        char msg[128];
        std::snprintf(msg, sizeof msg, "part %s: a triangle of quality gamma %.3f < %.2f at size %g mm, at ",
                      p.name.c_str(), s.min_gamma, min_gamma, size_mm);
        failure = msg + pipeline::format_position_mm(centre.x(), centre.y(), centre.z());
      }
      out.push_back(s);
    }
    if (failure.empty()) {
      tried.size_mm = size_mm;
      tried.back_size_mm = back_size_mm;
      if (retries) *retries = tried;
      return out;
    }
    tried.failed.push_back(failure);
    if (progress) progress->step(failure);
    const std::string larger = attempt ? " (and at " + std::to_string(attempt) + " larger sizes)" : std::string();
    if (attempt == max_retries)
      throw pipeline::Error(pipeline::ErrorKind::algorithm, failure + larger + ": try a smaller --size, or a lower --min-gamma");
    // Each retry costs more than the last: no retry past the budget the options are held to.
    const double next_triangles = pipeline::triangles_for_edge(area_mm2, std::min(size_mm, back_size_mm) * retry_size_factor);
    if (next_triangles > max_triangles) {
      char budget[160];
      std::snprintf(budget, sizeof budget, ": the next size, %g mm, would make ~%.2g triangles, more than %g million",
                    size_mm * retry_size_factor, next_triangles, max_triangles / 1e6);
      throw pipeline::Error(pipeline::ErrorKind::algorithm,
                            failure + larger + budget + "; try a larger --size, or a lower --min-gamma");
    }
    gmsh::model::remove();  // this attempt's model; the next one adds its own
    size_mm *= retry_size_factor;
    back_size_mm *= retry_size_factor;
  }
}

}  // namespace meshing
