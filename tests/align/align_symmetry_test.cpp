// The bounded closest-point queries of the symmetry search against plain CGAL: the capped
// distance must be min(exact distance, cap) for queries near and far from the surface, with
// and without a seed from another query.
#include <gtest/gtest.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "align_helpers.h"
#include "scan2cad/internal/align_symmetry.h"

namespace {

using Tree = CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel, CGAL::AABB_face_graph_triangle_primitive<pipeline::SurfaceMesh>>>;

TEST(align_symmetry, capped_distances_are_the_exact_distances_capped) {
  const auto mesh = scan2cad::load_surface_any_unit(align_test::data("headforms/NIOSH_medium_20k.stl"), 250.0);
  // Queries in the bounding box grown by 30 mm: some on the surface's scale, most far from it.
  const CGAL::Bbox_3 box = CGAL::Polygon_mesh_processing::bbox(mesh);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(box.xmin() - 30, box.xmax() + 30), uy(box.ymin() - 30, box.ymax() + 30),
      uz(box.zmin() - 30, box.zmax() + 30), near(-3.0, 3.0);
  std::vector<Eigen::Vector3d> queries;
  for (int i = 0; i < 1500; ++i) queries.emplace_back(ux(rng), uy(rng), uz(rng));
  // And points just off the surface (vertices moved by up to 3 mm per axis).
  int k = 0;
  for (auto v : mesh.vertices())
    if (k++ % 40 == 0) {
      const auto& p = mesh.point(v);
      queries.emplace_back(p.x() + near(rng), p.y() + near(rng), p.z() + near(rng));
    }
  Tree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.accelerate_distance_queries();
  const double cap_mm = 8.0;
  std::vector<double> exact;
  for (const auto& q : queries) exact.push_back(std::sqrt(tree.squared_distance(pipeline::Point(q.x(), q.y(), q.z()))));
  const auto within = std::count_if(exact.begin(), exact.end(), [&](double d) { return d < cap_mm; });
  ASSERT_GT(within, 400) << "enough queries near the surface to test";
  ASSERT_GT(long(exact.size()) - within, 400) << "enough queries beyond the cap to test";
  for (bool seeded : {false, true}) {
    const auto capped = scan2cad::internal::capped_distances(mesh, queries, cap_mm, seeded);
    ASSERT_EQ(capped.size(), queries.size());
    for (std::size_t i = 0; i < queries.size(); ++i)
      ASSERT_NEAR(capped[i], std::min(exact[i], cap_mm), 1e-9) << "query " << i << (seeded ? " seeded" : "");
  }
}

}  // namespace
