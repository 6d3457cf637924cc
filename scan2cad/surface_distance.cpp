// Symmetric surface distance by sampling + AABB-tree point-to-mesh distances (CGAL). Written out
// rather than PMP::approximate_Hausdorff_distance because we also need the 95th percentile.
#include "scan2cad/surface_distance.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Random.h>
#include <CGAL/hilbert_sort.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <vector>

#include "pipeline/error.h"

namespace PMP = CGAL::Polygon_mesh_processing;
using pipeline::SurfaceMesh;

namespace scan2cad {

namespace {

using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel, Primitive>>;

// Samples of `from` (n random points + every vertex) and their distances to `to`.
struct Measured {
  std::vector<pipeline::Point> samples;
  std::vector<double> distance_mm;
};

// The samples are put in Hilbert-curve order and each query starts from the previous sample's
// closest point: a hint that near lets the tree's traversal discard nearly every box at once,
// where CGAL's own hint (the nearest of the faces' reference points, from a k-d tree) has to be
// looked up per query. The distances are the same (the hint only bounds the search); the
// random samples come in random face order, so unsorted the previous answer is no hint at all.
Measured distances_from_to(const SurfaceMesh& from, const SurfaceMesh& to, std::size_t n) {
  Measured m;
  PMP::sample_triangle_mesh(from, std::back_inserter(m.samples),
                            CGAL::parameters::number_of_points_on_faces(n).random_seed(12345).do_sample_edges(false)
                                .do_sample_vertices(false));
  // every vertex once: CGAL samples them too by default, and with this loop they were counted twice
  for (auto v : from.vertices()) m.samples.push_back(from.point(v));
  CGAL::hilbert_sort(m.samples.begin(), m.samples.end());
  Tree tree(faces(to).first, faces(to).second, to);
  m.distance_mm.resize(m.samples.size());
  if (m.samples.empty()) return m;
  pipeline::Point hint = to.point(to.target(to.halfedge(*faces(to).begin())));  // any point of `to`
  for (std::size_t i = 0; i < m.samples.size(); ++i) {
    hint = tree.closest_point(m.samples[i], hint);
    m.distance_mm[i] = std::sqrt(CGAL::squared_distance(m.samples[i], hint));
  }
  return m;
}

bool in_any(const pipeline::Point& p, const Exclusion& ex) {
  for (const auto& b : ex.balls)
    if (CGAL::squared_distance(p, b.centre) < b.radius_mm * b.radius_mm) return true;
  for (const auto& h : ex.half_spaces)
    if ((p - h.point) * h.normal > 0) return true;
  return false;
}

// The largest distance among the samples outside `excluded`, and where it is; pools those
// distances into `all`. False if every sample is excluded.
bool worst_outside(const Measured& m, const Exclusion& excluded, double* max_mm, pipeline::Point* worst,
                   std::vector<double>& all) {
  bool any = false;
  for (std::size_t i = 0; i < m.samples.size(); ++i) {
    if (in_any(m.samples[i], excluded)) continue;
    all.push_back(m.distance_mm[i]);
    if (!any || m.distance_mm[i] > *max_mm) *max_mm = m.distance_mm[i], *worst = m.samples[i];
    any = true;
  }
  return any;
}

}  // namespace

std::vector<SurfaceDistance> surface_distances(const SurfaceMesh& a, const SurfaceMesh& b, std::size_t n,
                                               const std::vector<std::vector<Ball>>& exclusions) {
  std::vector<Exclusion> ex;
  for (const auto& balls : exclusions) ex.push_back({balls, {}});
  return surface_distances(a, b, n, ex);
}

std::vector<SurfaceDistance> surface_distances(const SurfaceMesh& a, const SurfaceMesh& b, std::size_t n,
                                               const std::vector<Exclusion>& exclusions) {
  if (a.number_of_faces() == 0 || b.number_of_faces() == 0)
    throw pipeline::bad_input("surface_distance", "a mesh has no faces");
  const Measured ab = distances_from_to(a, b, n), ba = distances_from_to(b, a, n);
  std::vector<SurfaceDistance> out;
  for (const auto& excluded : exclusions) {
    SurfaceDistance s;
    std::vector<double> all;
    if (!worst_outside(ab, excluded, &s.a_to_b_max_mm, &s.a_worst, all) ||
        !worst_outside(ba, excluded, &s.b_to_a_max_mm, &s.b_worst, all))
      throw pipeline::bad_input("surface_distance", "every sample lies in an excluded region");
    s.hausdorff_mm = std::max(s.a_to_b_max_mm, s.b_to_a_max_mm);
    double sum = 0;
    for (double x : all) sum += x;
    s.mean_mm = sum / double(all.size());
    const std::size_t k = std::size_t(0.95 * double(all.size() - 1));
    std::nth_element(all.begin(), all.begin() + long(k), all.end());
    s.p95_mm = all[k];
    out.push_back(s);
  }
  return out;
}

SurfaceDistance surface_distance(const SurfaceMesh& a, const SurfaceMesh& b, std::size_t n,
                                 const std::vector<Ball>& excluded) {
  return surface_distances(a, b, n, std::vector<Exclusion>{{excluded, {}}}).front();
}

double nearest_point_distance_mm(const pipeline::PointCloud& cloud, const pipeline::Point& p) {
  if (cloud.points.empty()) throw pipeline::bad_input("nearest_point_distance", "the point cloud is empty");
  double best = std::numeric_limits<double>::infinity();
  for (const auto& q : cloud.points) best = std::min(best, CGAL::squared_distance(p, q));
  return std::sqrt(best);
}

}  // namespace scan2cad
