// Helpers of repair: spikes, self-intersections, components (CGAL PMP where it has the tool).
#include "scan2cad/internal/cleanup.h"

#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/manifoldness.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <vector>

namespace PMP = CGAL::Polygon_mesh_processing;
using pipeline::Point;
using pipeline::SurfaceMesh;
using pipeline::Vector;

namespace scan2cad::internal {

// CGAL has no spike filter: a spike is a vertex that sticks out of the plane of its one-ring by
// more than `factor` × the ring's mean radius e (distance of the ring to its centroid, which the
// spike itself does not inflate); a smooth surface of curvature radius R has offset ≈ e²/(2R) ≪ e,
// a spike of 45° or steeper has offset ≥ e.
std::size_t remove_spikes(SurfaceMesh& mesh, double factor, int passes) {
  std::size_t moved = 0;
  for (int pass = 0; pass < passes; ++pass) {
    std::size_t moved_now = 0;
    for (auto v : mesh.vertices()) {
      if (mesh.is_border(v) || mesh.is_isolated(v)) continue;
      std::vector<Point> ring;
      for (auto h : CGAL::halfedges_around_target(mesh.halfedge(v), mesh)) ring.push_back(mesh.point(mesh.source(h)));
      if (ring.size() < 3) continue;
      Vector c(0, 0, 0);
      for (const auto& q : ring) c = c + (q - CGAL::ORIGIN);
      const Point centroid = CGAL::ORIGIN + c / double(ring.size());
      Vector n(0, 0, 0);  // ring normal: sum of cross products of consecutive ring points
      double edge = 0;
      for (std::size_t i = 0; i < ring.size(); ++i) {
        n = n + CGAL::cross_product(ring[i] - centroid, ring[(i + 1) % ring.size()] - centroid);
        edge += std::sqrt(CGAL::squared_distance(ring[i], centroid));
      }
      edge /= double(ring.size());
      const double nn = std::sqrt(n.squared_length());
      if (nn == 0 || edge == 0) continue;
      const double offset = std::abs((mesh.point(v) - centroid) * n) / nn;
      if (offset > factor * edge) {
        mesh.point(v) = centroid;
        ++moved_now;
      }
    }
    moved += moved_now;
    if (moved_now == 0) break;
  }
  return moved;
}

namespace {
std::set<pipeline::FaceIndex> self_intersecting_faces(const SurfaceMesh& mesh) {
  std::vector<std::pair<pipeline::FaceIndex, pipeline::FaceIndex>> pairs;
  PMP::self_intersections(mesh, std::back_inserter(pairs));
  std::set<pipeline::FaceIndex> faces;
  for (const auto& p : pairs) {
    faces.insert(p.first);
    faces.insert(p.second);
  }
  return faces;
}
}  // namespace

std::size_t count_self_intersecting_faces(const SurfaceMesh& mesh) { return self_intersecting_faces(mesh).size(); }

SelfIntersectionsCut remove_self_intersecting_faces(SurfaceMesh& mesh) {
  SelfIntersectionsCut result;
  const auto faces = self_intersecting_faces(mesh);
  result.crossing = faces.size();
  if (faces.empty()) return result;
  // also the faces around them: a one-face gap between two crossing sheets would reappear
  std::set<pipeline::FaceIndex> cut = faces;
  for (auto f : faces)
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      for (auto g : CGAL::faces_around_target(mesh.halfedge(v), mesh))
        if (g != SurfaceMesh::null_face()) cut.insert(g);
  for (auto f : cut) CGAL::Euler::remove_face(mesh.halfedge(f), mesh);
  mesh.collect_garbage();
  PMP::duplicate_non_manifold_vertices(mesh);
  result.faces_cut = cut.size();
  result.pieces = keep_largest_component(mesh);
  return result;
}

ComponentsKept keep_largest_component(SurfaceMesh& mesh) {
  ComponentsKept kept;
  auto component = mesh.add_property_map<pipeline::FaceIndex, std::size_t>("f:repair_component", 0).first;
  kept.components = PMP::connected_components(mesh, component);
  std::vector<double> area_mm2(kept.components, 0.0);
  double total_mm2 = 0;
  for (auto f : mesh.faces()) {
    const double a = PMP::face_area(f, mesh);
    area_mm2[component[f]] += a;
    total_mm2 += a;
  }
  if (kept.components > 1) {
    const std::size_t largest = std::size_t(std::max_element(area_mm2.begin(), area_mm2.end()) - area_mm2.begin());
    std::vector<double> sorted = area_mm2;
    std::partial_sort(sorted.begin(), sorted.begin() + 2, sorted.end(), std::greater<>());
    kept.second_area_share = total_mm2 > 0 ? sorted[1] / total_mm2 : 0.0;
    const std::size_t f0 = mesh.number_of_faces();
    PMP::keep_connected_components(mesh, std::vector<std::size_t>{largest}, component);
    kept.faces_removed = f0 - mesh.number_of_faces();
  }
  mesh.remove_property_map(component);
  mesh.collect_garbage();
  return kept;
}

}  // namespace scan2cad::internal
