// Symmetric surface distance by sampling + AABB-tree point-to-mesh distances (CGAL). Written out
// rather than PMP::approximate_Hausdorff_distance because we also need the 95th percentile.
#include "scan2cad/surface_distance.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Random.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <vector>

#include "pipeline/error.h"

namespace PMP = CGAL::Polygon_mesh_processing;
using pipeline::SurfaceMesh;

namespace scan2cad {

namespace {

using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel, Primitive>>;

std::vector<double> distances_from_to(const SurfaceMesh& from, const SurfaceMesh& to, std::size_t n,
                                      const std::vector<Ball>& excluded, pipeline::Point* worst) {
  std::vector<pipeline::Point> samples;
  PMP::sample_triangle_mesh(from, std::back_inserter(samples),
                            CGAL::parameters::number_of_points_on_faces(n).random_seed(12345).do_sample_edges(false));
  for (auto v : from.vertices()) samples.push_back(from.point(v));
  samples.erase(std::remove_if(samples.begin(), samples.end(),
                               [&](const pipeline::Point& p) {
                                 for (const auto& b : excluded)
                                   if (CGAL::squared_distance(p, b.centre) < b.radius_mm * b.radius_mm) return true;
                                 return false;
                               }),
                samples.end());
  if (samples.empty()) throw pipeline::bad_input("surface_distance", "every sample lies in an excluded region");
  Tree tree(faces(to).first, faces(to).second, to);
  tree.accelerate_distance_queries();
  std::vector<double> d(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) d[i] = std::sqrt(tree.squared_distance(samples[i]));
  *worst = samples[std::size_t(std::max_element(d.begin(), d.end()) - d.begin())];
  return d;
}

}  // namespace

SurfaceDistance surface_distance(const SurfaceMesh& a, const SurfaceMesh& b, std::size_t n,
                                 const std::vector<Ball>& excluded) {
  if (a.number_of_faces() == 0 || b.number_of_faces() == 0)
    throw pipeline::bad_input("surface_distance", "a mesh has no faces");
  SurfaceDistance s;
  std::vector<double> ab = distances_from_to(a, b, n, excluded, &s.a_worst),
                      ba = distances_from_to(b, a, n, excluded, &s.b_worst);
  s.a_to_b_max_mm = *std::max_element(ab.begin(), ab.end());
  s.b_to_a_max_mm = *std::max_element(ba.begin(), ba.end());
  s.hausdorff_mm = std::max(s.a_to_b_max_mm, s.b_to_a_max_mm);
  std::vector<double> all = ab;
  all.insert(all.end(), ba.begin(), ba.end());
  double sum = 0;
  for (double x : all) sum += x;
  s.mean_mm = sum / double(all.size());
  const std::size_t k = std::size_t(0.95 * double(all.size() - 1));
  std::nth_element(all.begin(), all.begin() + long(k), all.end());
  s.p95_mm = all[k];
  return s;
}

}  // namespace scan2cad
