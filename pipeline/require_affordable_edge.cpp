#include "pipeline/require_affordable_edge.h"

#include <CGAL/Polygon_mesh_processing/measure.h>

#include <cmath>
#include <cstdio>

#include "pipeline/error.h"

namespace pipeline {

double triangles_for_edge(double area_mm2, double edge_mm) { return area_mm2 / (std::sqrt(3.0) / 4.0 * edge_mm * edge_mm); }

void require_affordable_edge(const std::string& option, double edge_mm, const SurfaceMesh& surface,
                             double max_triangles) {
  if (!(edge_mm > 0)) return;
  const double area_mm2 = CGAL::Polygon_mesh_processing::area(surface);
  const double triangles = triangles_for_edge(area_mm2, edge_mm);
  if (!(triangles > max_triangles)) return;
  char what[200];
  std::snprintf(what, sizeof what, "would make ~%.2g triangles on this %.0f mm2 surface, more than %.0f million: choose a longer edge",
                triangles, area_mm2, max_triangles / 1e6);
  throw Error(ErrorKind::usage, option + " " + format_number(edge_mm) + " mm " + what);
}

}  // namespace pipeline
