// Tests of scan2cad::mark_border_corners and of remesh_parts on an open sheet whose rim has a
// jog: the generated three-size XL cup's rim had a 1.05 mm step (turns of 66 and -72 deg at its
// two ends) that remesh_parts kept as two fixed corners, and surface_mesh failed there with a
// gamma 0.287 triangle. A step like that is noise; a real corner (turns of one sign) is kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "pipeline/surface_mesh.h"
#include "scan2cad/fit.h"

namespace {

using pipeline::Point;
using pipeline::SurfaceMesh;

constexpr int sheet_columns = 61, sheet_rows = 41;  // 1 mm grid: a 60 x 40 mm sheet
constexpr int step_column = 31;     // rim vertices from this column on are raised by step_mm
constexpr double step_mm = 0.6;     // and the first of them is moved back to x = 30.3: the
constexpr double step_x_mm = 30.3;  // step (30, 0)-(30.3, 0.6) is 0.67 mm long, turns +-63 deg
// (CGAL 5.5's relaxation inside isotropic_remeshing smooths a rim vertex that turns by less than
// 60 deg whatever the vertex constraints say, so a gentler step would vanish anyway.)

// A flat respirator-like sheet (part 0), its rim the rectangle's outline. With `step`, the rim
// along y = 0 has the jog; with `chamfer`, the corner at (0, 0) is cut by a 1 mm chamfer (two
// 45 deg turns of the same sign 1.4 mm apart: still a 90 deg corner).
SurfaceMesh sheet(bool step, bool chamfer) {
  SurfaceMesh mesh;
  auto part = mesh.add_property_map<pipeline::FaceIndex, int>(pipeline::part_property, 0).first;
  std::vector<pipeline::VertexIndex> v;
  for (int j = 0; j < sheet_rows; ++j)
    for (int i = 0; i < sheet_columns; ++i) {
      double y = j;
      double x = i;
      if (step && j == 0 && i >= step_column) y = step_mm;
      if (step && j == 0 && i == step_column) x = step_x_mm;
      v.push_back(mesh.add_vertex(Point(x, y, 0)));
    }
  auto at = [&](int i, int j) { return v[std::size_t(j * sheet_columns + i)]; };
  for (int j = 0; j + 1 < sheet_rows; ++j)
    for (int i = 0; i + 1 < sheet_columns; ++i) {
      if (chamfer && i == 0 && j == 0) {  // only the upper-left half of the corner cell
        part[mesh.add_face(at(1, 0), at(1, 1), at(0, 1))] = 0;
        continue;
      }
      if (step && i + 1 == step_column && j == 0) {  // the other diagonal: the step's top vertex
        part[mesh.add_face(at(i, j), at(i + 1, j), at(i, j + 1))] = 0;  // lies left of this one
        part[mesh.add_face(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1))] = 0;
        continue;
      }
      part[mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1))] = 0;
      part[mesh.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1))] = 0;
    }
  mesh.collect_garbage();  // drops the chamfer's isolated corner vertex
  return mesh;
}

std::vector<Point> marked(const SurfaceMesh& mesh, double jog_mm, std::size_t* unmarked) {
  SurfaceMesh m = mesh;
  auto corner = m.add_property_map<pipeline::VertexIndex, bool>("v:test_corner", false).first;
  *unmarked = scan2cad::mark_border_corners(m, 20.0, jog_mm, corner);
  std::vector<Point> out;
  for (auto vi : m.vertices())
    if (corner[vi]) out.push_back(m.point(vi));
  std::sort(out.begin(), out.end());
  return out;
}

TEST(mark_border_corners, a_jog_is_not_a_corner_and_a_chamfered_corner_is) {
  std::size_t unmarked = 0;
  // Plain rectangle: its 4 corners.
  EXPECT_EQ(marked(sheet(false, false), 1.75, &unmarked),
            (std::vector<Point>{Point(0, 0, 0), Point(0, 40, 0), Point(60, 0, 0), Point(60, 40, 0)}));
  EXPECT_EQ(unmarked, 0u);
  // The step's two vertices turn by +-63 deg: corners by angle, but one jog 0.67 mm long.
  const auto with_step = marked(sheet(true, false), 1.75, &unmarked);
  EXPECT_EQ(unmarked, 2u);
  EXPECT_EQ(with_step.size(), 4u);
  EXPECT_EQ(std::count(with_step.begin(), with_step.end(), Point(30, 0, 0)), 0);
  // With a jog length shorter than the step, both stay corners (the option means what it says).
  EXPECT_EQ(marked(sheet(true, false), 0.5, &unmarked).size(), 6u);
  EXPECT_EQ(unmarked, 0u);
  // The chamfer's two 45 deg turns add up to 90 deg: both ends stay corners.
  const auto chamfered = marked(sheet(false, true), 1.75, &unmarked);
  EXPECT_EQ(unmarked, 0u);
  EXPECT_EQ(std::count(chamfered.begin(), chamfered.end(), Point(1, 0, 0)), 1);
  EXPECT_EQ(std::count(chamfered.begin(), chamfered.end(), Point(0, 1, 0)), 1);
}

TEST(remesh_parts, a_jog_in_the_rim_leaves_no_poor_triangle) {
  SurfaceMesh mesh = scan2cad::remesh_parts(sheet(true, false), "respirator", 7.0);
  scan2cad::improve_triangles(mesh);
  // surface_mesh's acceptance threshold is 0.3.
  EXPECT_GE(scan2cad::min_triangle_gamma(mesh), 0.3);
  // The step is gone: no rim edge is shorter than a quarter of the target (with the step's two
  // vertices fixed as corners, its 0.67 mm edge stays).
  double shortest_rim_edge = 1e300;
  for (auto e : mesh.edges())
    if (mesh.is_border(e))
      shortest_rim_edge = std::min(shortest_rim_edge, std::sqrt(CGAL::squared_distance(
                                                          mesh.point(mesh.vertex(e, 0)), mesh.point(mesh.vertex(e, 1)))));
  EXPECT_GE(shortest_rim_edge, 0.25 * 7.0);
  std::printf("min gamma %.3f, shortest rim edge %.2f mm\n", scan2cad::min_triangle_gamma(mesh), shortest_rim_edge);
  // The four real corners are still there (the step raised the rim right of it, (60, 0) too).
  std::size_t found = 0;
  for (auto vi : mesh.vertices())
    for (const Point& c : {Point(0, 0, 0), Point(0, 40, 0), Point(60, step_mm, 0), Point(60, 40, 0)})
      found += mesh.point(vi) == c;
  EXPECT_EQ(found, 4u);
}

}  // namespace
