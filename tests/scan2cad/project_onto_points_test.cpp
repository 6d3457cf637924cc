// project_onto_points and untangle_crossings (scan2cad/internal/project_onto_points.h) on a
// sphere whose points are exact, so every tolerance below is a discretisation error.
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <cmath>
#include <utility>
#include <vector>

#include "data/generator/random.h"
#include "scan2cad/internal/project_onto_points.h"
#include "tests/scan2cad/test_meshes.h"

namespace {

using PN = std::pair<pipeline::Point, pipeline::Vector>;

// n points on the sphere of radius r, area-uniform, with their outward normals
std::vector<PN> sphere_points(double r, std::size_t n) {
  generator::Rng rng{3};
  std::vector<PN> pn;
  for (std::size_t i = 0; i < n; ++i) {
    const pipeline::Vector d(rng.normal(), rng.normal(), rng.normal());
    const pipeline::Vector u = d / std::sqrt(d.squared_length());
    pn.push_back({CGAL::ORIGIN + r * u, u});
  }
  return pn;
}

bool self_intersects(const pipeline::SurfaceMesh& m) {
  return CGAL::Polygon_mesh_processing::does_self_intersect(m);
}

}  // namespace

// A 20 mm sphere meshed with ~2 mm edges, moved 0.5 mm outward: the projection takes every
// vertex back onto the points' sphere. Tolerance 0.005 mm: a quadric over 24 points within
// ~1 mm on a 20 mm sphere differs from it by O(h^4 / r^3) ~ 1e-5 mm (measured: < 1e-4 mm).
TEST(project_onto_points, takes_the_vertices_of_an_offset_sphere_back_onto_it) {
  const double r = 20;
  auto mesh = test_meshes::mesh_of(test_meshes::sphere_soup(r + 0.5, 32));
  const auto pn = sphere_points(r, 20000);
  const scan2cad::internal::PointTree tree(pn);
  const double sign = scan2cad::internal::point_normal_sign(mesh, pn, tree);
  EXPECT_EQ(sign, 1.0);
  const std::vector<pipeline::VertexIndex> all(mesh.vertices().begin(), mesh.vertices().end());
  const auto ps = scan2cad::internal::project_onto_points(mesh, all, sign, pn, tree, 24, 0.5, 3.0);
  std::printf("moved %zu of %zu, mean move %.4f mm, largest radial error %.4f mm\n", ps.moved, all.size(),
              ps.mean_move_mm, test_meshes::max_radial_error(mesh, r));
  EXPECT_EQ(ps.moved, all.size());
  EXPECT_NEAR(ps.mean_move_mm, 0.5, 0.02);
  EXPECT_LT(test_meshes::max_radial_error(mesh, r), 0.005);
}

// The pole of the sphere pushed through to beyond the other pole: its fan crosses the faces
// around the other pole. untangle_crossings cuts both regions out, fills each gap with a faired
// patch and projects the patch onto the points: no crossing is left, the mesh is closed again,
// and every vertex is back on the sphere. Tolerance 0.005 mm as above (measured: < 1e-4 mm);
// without the projection of the patches (largest move 1e-9 mm) their fairing is 0.011 mm off.
TEST(untangle_crossings, refills_a_vertex_pushed_through_the_surface_onto_the_points) {
  const double r = 20;
  auto mesh = test_meshes::mesh_of(test_meshes::sphere_soup(r, 32));
  pipeline::VertexIndex top;
  for (auto v : mesh.vertices())
    if (top == pipeline::VertexIndex() || mesh.point(v).z() > mesh.point(top).z()) top = v;
  mesh.point(top) = pipeline::Point(0.3, 0.2, -r - 3);
  ASSERT_TRUE(self_intersects(mesh));
  const auto pn = sphere_points(r, 20000);
  const scan2cad::internal::PointTree tree(pn);
  const auto us = scan2cad::internal::untangle_crossings(mesh, 1.0, pn, tree, 24, 0.5, 3.0, 3);
  std::printf("%d rounds, %zu faces cut, %zu gaps filled, %zu vertices projected, %zu crossing left, "
              "largest radial error %.4f mm\n",
              us.rounds, us.faces_cut, us.gaps_filled, us.vertices_projected, us.crossing_left,
              test_meshes::max_radial_error(mesh, r));
  EXPECT_GE(us.rounds, 1);
  EXPECT_GE(us.gaps_filled, 2u);  // at both poles
  EXPECT_EQ(us.crossing_left, 0u);
  EXPECT_FALSE(self_intersects(mesh));
  EXPECT_TRUE(CGAL::is_closed(mesh));
  EXPECT_LT(test_meshes::max_radial_error(mesh, r), 0.005);
}

// A gap that reaches a border the mesh had before (a scan hole, which repair fills) stays open.
TEST(untangle_crossings, leaves_a_gap_merged_with_a_scan_hole_open) {
  const double r = 20;
  auto mesh = test_meshes::mesh_of(test_meshes::sphere_soup(r, 32));
  // the scan hole: the faces around the south pole
  std::vector<pipeline::FaceIndex> hole;
  for (auto f : mesh.faces()) {
    bool south = true;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) south &= mesh.point(v).z() < -0.97 * r;
    if (south) hole.push_back(f);
  }
  ASSERT_FALSE(hole.empty());
  for (auto f : hole) CGAL::Euler::remove_face(mesh.halfedge(f), mesh);
  mesh.collect_garbage();
  // a vertex beside the hole's rim pushed through the north cap
  pipeline::VertexIndex rim;
  for (auto v : mesh.vertices())
    if (!mesh.is_border(v) && mesh.point(v).z() < -0.9 * r) rim = v;
  ASSERT_NE(rim, pipeline::VertexIndex());
  mesh.point(rim) = pipeline::Point(0, 0, r + 3);
  ASSERT_TRUE(self_intersects(mesh));
  const auto pn = sphere_points(r, 20000);
  const scan2cad::internal::PointTree tree(pn);
  const auto us = scan2cad::internal::untangle_crossings(mesh, 1.0, pn, tree, 24, 0.5, 3.0, 3);
  EXPECT_EQ(us.crossing_left, 0u);
  EXPECT_FALSE(CGAL::is_closed(mesh));  // the scan hole, with the cut beside it, is still open
  EXPECT_GE(us.gaps_filled, 1u);        // the cut at the north cap was filled
}
