// scan2cad::build_part_model's topology (internal/number_topology.h) on a one-part patch, a
// respirator's case: its border is one closed curve, whose single point createTopology put on a
// node of its choosing (by memory address: the medium_onesize respirator gave four different
// surface.msh files in five runs from other folders). The point now sits on the curve's smallest
// node and the curve's lines start there and walk it in order.
#include <gtest/gtest.h>

#include <gmsh.h>

#include <algorithm>
#include <vector>

#include "pipeline/gmsh_session.h"
#include "pipeline/surface_mesh.h"
#include "scan2cad/fit.h"

namespace {

// An n × n grid of unit squares, two triangles each, all part 0, its vertices added in the order
// i * 29 mod (n + 1)², so that vertex tags (index + 1) do not follow the border.
pipeline::SurfaceMesh shuffled_patch(int n) {
  const int count = (n + 1) * (n + 1);
  pipeline::SurfaceMesh mesh;
  auto part = mesh.add_property_map<pipeline::FaceIndex, int>(pipeline::part_property, 0).first;
  std::vector<pipeline::VertexIndex> at(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const int k = int((long(i) * 29) % count);  // 29 is prime to the count of 100 used below
    at[std::size_t(k)] = mesh.add_vertex(pipeline::Point(k % (n + 1), k / (n + 1), 0.1 * ((k * 7) % 5)));
  }
  auto v = [&](int x, int y) { return at[std::size_t(y * (n + 1) + x)]; };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      part[mesh.add_face(v(x, y), v(x + 1, y), v(x + 1, y + 1))] = 0;
      part[mesh.add_face(v(x, y), v(x + 1, y + 1), v(x, y + 1))] = 0;
    }
  return mesh;
}

}  // namespace

TEST(number_topology, a_closed_border_starts_at_its_smallest_node) {
  const pipeline::GmshSession session;
  const auto parts = scan2cad::build_part_model(shuffled_patch(9), "respirator", false);
  ASSERT_EQ(parts.size(), 1u);
  gmsh::vectorpair curves, points;
  gmsh::model::getEntities(curves, 1);
  gmsh::model::getEntities(points, 0);
  ASSERT_EQ(curves.size(), 1u);  // the border, closed
  ASSERT_EQ(points.size(), 1u);
  std::vector<int> up, ends;
  gmsh::model::getAdjacencies(1, curves[0].second, up, ends);
  ASSERT_EQ(ends, (std::vector<int>{points[0].second, points[0].second}));
  std::vector<std::size_t> point_node, lines, elements;
  std::vector<double> xyz, parametric;
  gmsh::model::mesh::getNodes(point_node, xyz, parametric, 0, points[0].second, false, false);
  gmsh::model::mesh::getElementsByType(1, elements, lines, curves[0].second);
  ASSERT_EQ(point_node.size(), 1u);
  ASSERT_EQ(lines.size(), 2u * 36);  // 36 border edges of the 9 × 9 patch
  EXPECT_EQ(point_node[0], *std::min_element(lines.begin(), lines.end()));
  EXPECT_EQ(lines.front(), point_node[0]);
  EXPECT_EQ(lines.back(), point_node[0]);
  for (std::size_t k = 2; k + 1 < lines.size(); k += 2) EXPECT_EQ(lines[k], lines[k - 1]) << "lines walk the curve";
  // The curve's own nodes are the other 35, in tag order, and the point's node is not among them.
  std::vector<std::size_t> own;
  gmsh::model::mesh::getNodes(own, xyz, parametric, 1, curves[0].second, false, false);
  EXPECT_EQ(own.size(), 35u);
  EXPECT_TRUE(std::is_sorted(own.begin(), own.end()));
  EXPECT_EQ(std::count(own.begin(), own.end(), point_node[0]), 0);
  // The point's coordinates are those of its node (the grid's x, y from the node's vertex index).
  const long k = long(point_node[0]) - 1;  // vertex index: the k-th added, at grid position k * 29 mod 100
  const long g = (k * 29) % 100;
  EXPECT_EQ(xyz.size(), 3u * 35);
  std::vector<std::size_t> p;
  std::vector<double> pxyz;
  gmsh::model::mesh::getNodes(p, pxyz, parametric, 0, points[0].second, false, false);
  EXPECT_EQ(pxyz[0], double(g % 10));
  EXPECT_EQ(pxyz[1], double(g / 10));
}
