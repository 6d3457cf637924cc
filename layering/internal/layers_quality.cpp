// Element quality measures of the layering stage (Verdict-style scaled Jacobian, volume) and the
// model-wide face intersection count. Hand-written: a few lines of vector algebra.
#include <Eigen/Geometry>

#include <cmath>

#include "layering/internal/layers_columns.h"
#include "layering/internal/layers_geometry.h"
#include "layering/layers.h"

namespace layering {

double wedge_scaled_jacobian(const Eigen::Vector3d* p) {
  // Corner c: its two triangle edges (counter-clockwise seen from the top) and its column edge.
  static const int corner[6][4] = {{0, 1, 2, 3}, {1, 2, 0, 4}, {2, 0, 1, 5},
                                   {3, 5, 4, 0}, {4, 3, 5, 1}, {5, 4, 3, 2}};
  double worst = 1e300;
  for (const auto& c : corner) {
    const Eigen::Vector3d a = p[c[1]] - p[c[0]], b = p[c[2]] - p[c[0]], h = p[c[3]] - p[c[0]];
    const double l = a.norm() * b.norm() * h.norm();
    const double j = l > 0 ? a.cross(b).dot(h) / l : -1.0;
    worst = std::min(worst, j);
  }
  return worst * 2.0 / std::sqrt(3.0);
}

double wedge_volume(const Eigen::Vector3d* p) {
  auto tet = [&](int a, int b, int c, int d) { return (p[b] - p[a]).cross(p[c] - p[a]).dot(p[d] - p[a]) / 6.0; };
  return tet(0, 1, 2, 3) + tet(1, 2, 3, 4) + tet(2, 3, 4, 5);
}

std::size_t count_intersecting_faces(const FeModel& model) {
  std::vector<internal::Tri> tris;
  std::vector<std::pair<int, int>> owner;
  internal::element_faces(model, &tris, &owner);
  return internal::intersecting_triangles(model.nodes, tris).size();
}

}  // namespace layering
