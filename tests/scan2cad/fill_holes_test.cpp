// fill_holes on a sphere with holes cut into it.
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/border.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <vector>

#include "scan2cad/fill_holes.h"
#include "test_meshes.h"

namespace {

// Removes the faces whose centroid lies within `radius` of `centre`.
void cut_hole(pipeline::SurfaceMesh& m, const pipeline::Point& centre, double radius) {
  std::vector<pipeline::FaceIndex> cut;
  for (auto f : m.faces()) {
    pipeline::Vector c(0, 0, 0);
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) c = c + (m.point(v) - CGAL::ORIGIN);
    if (CGAL::squared_distance(CGAL::ORIGIN + c / 3.0, centre) < radius * radius) cut.push_back(f);
  }
  for (auto f : cut) CGAL::Euler::remove_face(m.halfedge(f), m);
  m.collect_garbage();
}

std::size_t loops(const pipeline::SurfaceMesh& m) {
  std::vector<pipeline::SurfaceMesh::Halfedge_index> h;
  CGAL::Polygon_mesh_processing::extract_boundary_cycles(m, std::back_inserter(h));
  return h.size();
}

}  // namespace

TEST(fill_holes, closes_a_10mm_hole_on_the_sphere_it_belongs_to) {
  const double r = 50;
  auto m = test_meshes::mesh_of(test_meshes::sphere_soup(r, 90));  // edges ≈ 1.7 mm
  cut_hole(m, {r, 0, 0}, 5.0);
  ASSERT_EQ(loops(m), 1u);
  const auto holes = scan2cad::fill_holes(m, scan2cad::ScanKind::head);
  ASSERT_EQ(holes.size(), 1u);
  EXPECT_TRUE(holes[0].filled);
  EXPECT_TRUE(holes[0].faired);
  // faces with centroids within 5 mm are cut: the border lies 5 mm to 5 mm + one edge (1.75 mm) out
  EXPECT_GE(holes[0].diameter_mm, 9.0);
  EXPECT_LE(holes[0].diameter_mm, 13.6);
  EXPECT_TRUE(CGAL::is_closed(m));
  // A faired patch follows the sphere: a flat cap would sit at the sagitta 5²/(2·50) = 0.25 mm
  // below it; fairing (C1 continuity) must do clearly better than flat: ≤ 0.1 mm.
  double worst = 0;
  for (auto v : m.vertices())
    worst = std::max(worst, std::abs(std::sqrt((m.point(v) - CGAL::ORIGIN).squared_length()) - r));
  EXPECT_LT(worst, 0.1);
}

TEST(fill_holes, respirator_keeps_its_largest_loop_open) {
  // "Respirator": the sphere's front half (an open cup with a 100 mm rim) with a 12 mm hole.
  auto m = test_meshes::mesh_of(test_meshes::sphere_soup(50, 60));
  cut_hole(m, {0, 0, -50}, 70.0);  // removes the back: the rim
  cut_hole(m, {0, 0, 50}, 6.0);    // a scan hole
  ASSERT_EQ(loops(m), 2u);
  const auto holes = scan2cad::fill_holes(m, scan2cad::ScanKind::respirator);
  ASSERT_EQ(holes.size(), 2u);
  EXPECT_TRUE(holes[0].kept_open);
  EXPECT_GT(holes[0].perimeter_mm, holes[1].perimeter_mm);
  EXPECT_TRUE(holes[1].filled);
  EXPECT_EQ(loops(m), 1u);
}

// A closed shell has no rim: a few open edges in it (the real Conforming cup's 4 mm gap) were kept
// open as its "rim". The rim goes round the face: it is longer than the object's extent.
TEST(fill_holes, respirator_without_a_rim_long_enough_fills_every_loop) {
  auto m = test_meshes::mesh_of(test_meshes::sphere_soup(50, 60));
  cut_hole(m, {0, 0, 50}, 6.0);
  const auto holes = scan2cad::fill_holes(m, scan2cad::ScanKind::respirator);
  ASSERT_EQ(holes.size(), 1u);
  EXPECT_LT(holes[0].perimeter_mm, 100.0);
  EXPECT_FALSE(holes[0].kept_open);
  EXPECT_TRUE(holes[0].filled);
  EXPECT_TRUE(CGAL::is_closed(m));
}

TEST(fill_holes, head_fills_every_loop) {
  auto m = test_meshes::mesh_of(test_meshes::sphere_soup(50, 60));
  cut_hole(m, {0, 0, -50}, 70.0);
  const auto holes = scan2cad::fill_holes(m, scan2cad::ScanKind::head);
  ASSERT_EQ(holes.size(), 1u);
  EXPECT_TRUE(holes[0].filled);
  EXPECT_TRUE(CGAL::is_closed(m));
}

// The edges inside a fill follow fill_edge_mm, finer than the loop's: a reconstructed head's loops
// have ~3 mm edges, and complete_by_symmetry reshapes a fill only as finely as it is meshed. An
// inverted density (loop edge over fill edge upside down) filled at the loop's size and only a
// slow repair test saw it, through a table's lowest point (sweep L). Liepa's refinement stops
// splitting a triangle once its centroid is within a vertex's scale / density of the vertex, so
// the inner edges come out longer than the scale asked for: 1.70 and 1.68 times it here
// (fill_holes.h); the bounds allow the factor 1.3-2.1 and ask that the size follow the request.
TEST(fill_hole, edges_inside_a_fill_follow_the_requested_length) {
  std::vector<double> mean_mm;
  for (const double fill_edge_mm : {1.0, 0.7}) {
    SCOPED_TRACE(fill_edge_mm);
    auto m = test_meshes::mesh_of(test_meshes::sphere_soup(50, 45));  // edges ≈ 3.5 mm
    cut_hole(m, {50, 0, 0}, 10.0);
    std::vector<pipeline::SurfaceMesh::Halfedge_index> border;
    CGAL::Polygon_mesh_processing::extract_boundary_cycles(m, std::back_inserter(border));
    ASSERT_EQ(border.size(), 1u);
    std::vector<pipeline::VertexIndex> inner;
    const scan2cad::HoleInfo hole = scan2cad::fill_hole(m, border[0], fill_edge_mm, nullptr, &inner);
    ASSERT_TRUE(hole.filled);
    const double loop_edge_mm = hole.perimeter_mm / double(hole.boundary_edges);
    std::set<pipeline::VertexIndex> is_inner(inner.begin(), inner.end());
    double sum = 0;
    std::size_t n = 0;
    for (auto e : m.edges()) {
      const auto a = m.vertex(e, 0), b = m.vertex(e, 1);
      if (!is_inner.count(a) || !is_inner.count(b)) continue;
      sum += std::sqrt(CGAL::squared_distance(m.point(a), m.point(b)));
      ++n;
    }
    ASSERT_GT(n, 20u);
    mean_mm.push_back(sum / double(n));
    std::printf("loop edge %.2f mm, fill edge %.2f asked, %.2f mean over %zu inner edges\n", loop_edge_mm,
                fill_edge_mm, mean_mm.back(), n);
    EXPECT_GT(loop_edge_mm, 3.0);
    EXPECT_GT(mean_mm.back() / fill_edge_mm, 1.3);
    EXPECT_LT(mean_mm.back() / fill_edge_mm, 2.1);
  }
  EXPECT_NEAR(mean_mm[1] / mean_mm[0], 0.7, 0.1);
}
