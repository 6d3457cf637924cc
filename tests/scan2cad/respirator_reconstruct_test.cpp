// Respirator cups through reconstruct + repair (issue 2): a generated N95 cup is scanned all
// round (both sides of its 1.5 mm wall, 0.2 mm noise, 0.5 % outliers, one random 10–20 mm
// hole: generate_scan's defaults). reconstruct separates the two sides of the wall and keeps
// the inner one (toward the face); repair must give a clean open disk — manifold, no
// self-intersections, one boundary loop (the rim), disk topology — facing the face and lying
// on the scanned inner surface, every output point within 1 mm of the cup. Before, advancing front on the whole cup tore the inner side
// apart (400 self-intersecting faces, 117 holes filled).
#include <gtest/gtest.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "data/generator/generate_scan.h"
#include "scan2cad/reconstruct.h"
#include "scan2cad/repair.h"
#include "scan2cad/surface_distance.h"

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using pipeline::SurfaceMesh;

struct CupRun {
  scan2cad::ReconstructStats stats;
  scan2cad::RepairReport report;
  SurfaceMesh clean, repaired;
};

CupRun make_cup_run(const std::string& id) {
  generator::GenerateRequest rq;
  rq.kind = "respirator";
  rq.id = id;
  rq.params_path = std::string(SOURCE_DIR) + "/data/generator/respirators.json";
  rq.seed = 1;
  const auto scan = generator::generate_scan(rq);
  CupRun run;
  run.clean = scan.clean_mesh;
  scan2cad::ReconstructOptions opt;
  opt.method = scan2cad::parse_reconstruct_method("auto", scan2cad::ScanKind::respirator);
  const auto rec = scan2cad::reconstruct(scan.cloud, scan2cad::ScanKind::respirator, opt, &run.stats);
  pipeline::PolygonSoup soup;
  for (auto v : rec.vertices()) soup.points.push_back(rec.point(v));
  for (auto f : rec.faces()) {
    soup.polygons.emplace_back();
    for (auto v : CGAL::vertices_around_face(rec.halfedge(f), rec)) soup.polygons.back().push_back(std::size_t(v));
  }
  run.repaired = scan2cad::repair(soup, scan2cad::ScanKind::respirator, {}, &run.report);
  return run;
}

// One reconstruct + repair per cup and test process, shared by the tests below.
const CupRun& cup_run(const std::string& id) {
  static std::map<std::string, CupRun> runs;
  auto it = runs.find(id);
  if (it == runs.end()) it = runs.emplace(id, make_cup_run(id)).first;
  return it->second;
}

void check_cup(const std::string& id) {
  SCOPED_TRACE(id);
  const CupRun& run = cup_run(id);
  const SurfaceMesh& out = run.repaired;
  // the two sides were found: the median wall is the model's 1.5 mm within the 0.2 mm noise
  EXPECT_TRUE(run.stats.thin_shell);
  EXPECT_NEAR(run.stats.wall_mm, 1.5, 0.3);
  // a clean open disk: one piece, one boundary loop (the rim), V − E + F = 1
  EXPECT_FALSE(run.report.closed);
  EXPECT_TRUE(run.report.manifold);
  EXPECT_FALSE(run.report.self_intersecting_after);
  EXPECT_EQ(run.report.boundary_loops_after, 1u);
  std::vector<std::size_t> component(out.number_of_faces());
  EXPECT_EQ(PMP::connected_components(out, CGAL::make_property_map(component)), 1u);
  EXPECT_EQ(long(out.number_of_vertices()) - long(out.number_of_edges()) + long(out.number_of_faces()), 1);

  // The inner side: the clean model's inner sheet (faces facing the face, n·z < −0.1, the
  // steep band by the rim included) has an output face within `near_mm` (the inner side is
  // there, up to the rim), and where it has, that face's normal faces the same way.
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel, Primitive>>;
  Tree tree(faces(out).first, faces(out).second, out);
  tree.accelerate_distance_queries();
  std::size_t inner = 0, near = 0, facing = 0;
  double worst = 0;
  const double near_mm = 0.5;  // noise σ 0.2 mm: 2.5 σ
  const SurfaceMesh& clean = run.clean;
  for (auto f : clean.faces()) {
    const auto n = PMP::compute_face_normal(f, clean);
    if (n.z() > -0.1) continue;  // outer sheet and rim strip
    ++inner;
    const auto h = clean.halfedge(f);
    const pipeline::Point c = CGAL::centroid(clean.point(clean.source(h)), clean.point(clean.target(h)),
                                             clean.point(clean.target(clean.next(h))));
    const auto hit = tree.closest_point_and_primitive(c);
    const double d = std::sqrt(CGAL::squared_distance(c, hit.first));
    worst = std::max(worst, d);
    if (d > near_mm) continue;
    ++near;
    facing += PMP::compute_face_normal(hit.second, out) * n > 0.5;
  }
  ASSERT_GT(inner, 1000u);
  // output → clean surface: nothing off the cup, within the heads' Hausdorff bound. Measured
  // 0.742 / 0.749 mm (onesize / threesize-xl, seed 1); threesize-xl was at 2.41 mm once, at the
  // rim's nose notch. (The other direction is not bounded: the output is the inner side only.)
  const auto d = scan2cad::surface_distance(out, clean);
  EXPECT_LE(d.a_to_b_max_mm, 1.0) << "farthest output point " << d.a_worst;
  std::printf("%-13s wall %.2f mm | inner side within %.1f mm: %.2f %%, of these facing the same way: %.2f %%, farthest "
              "%.2f mm | output->clean max %.3f mm | faces %zu, %zu holes filled, %zu self-intersecting "
              "removed\n",
              id.c_str(), run.stats.wall_mm, near_mm, 100.0 * double(near) / double(inner),
              100.0 * double(facing) / double(near), worst, d.a_to_b_max_mm, std::size_t(out.number_of_faces()),
              run.report.holes.size() - 1, run.report.self_intersecting_faces_removed);
  // the random hole (≤ 20 mm across, through both sides) is filled smoothly: allow 2 %
  EXPECT_GT(double(near), 0.98 * double(inner)) << "farthest " << worst << " mm";
  EXPECT_GT(double(facing), 0.99 * double(near));
}

}  // namespace

TEST(respirator_reconstruct, onesize_cup_keeps_its_inner_side_as_a_clean_open_disk_on_the_cup) { check_cup("onesize"); }
TEST(respirator_reconstruct, threesize_xl_cup_keeps_its_inner_side_as_a_clean_open_disk_on_the_cup) { check_cup("threesize-xl"); }
