// remove_support_plane: the table a headform stood on is found and removed, on the real NIOSH
// medium head (its points for reconstruct, its faces for repair), and nothing is removed from a
// head that stood on none (its flat neck cap stays).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <CGAL/Random.h>

#include "data/generator/generate_scan.h"
#include "data/generator/scanner_artifacts.h"
#include "pipeline/read_scan.h"
#include "scan2cad/remove_support_plane.h"
#include "scan2cad/repair.h"
#include "test_meshes.h"

// (names unlike the other scan2cad tests': they share one unity build)
namespace {

using ScanPoint = std::pair<pipeline::Point, pipeline::Vector>;
const std::string niosh_medium_stl = std::string(SHARED_DATA_DIR) + "/headforms/NIOSH_medium_20k.stl";

// 60,000 points of NIOSH medium with 0.3 mm of noise along the normals. Its neck ends in a flat
// cap at y = -162.3 mm, 137 mm across.
std::vector<ScanPoint> niosh_scan_points() {
  generator::Rng rng{7};
  generator::ScanOptions so;
  so.points = 60000;
  so.noise_mm = 0.3;
  so.outliers.fraction = 0;
  std::vector<ScanPoint> pn;
  for (const auto& p : generator::scan_surface(generator::triangles_of(pipeline::read_scan(niosh_medium_stl).soup), so, rng).points)
    pn.push_back({p, pipeline::Vector(0, 0, 0)});
  return pn;
}
constexpr double niosh_cap_y_mm = -162.3;

// The generated one-size cup, seed 1.
generator::GenerateRequest onesize_cup_request() {
  generator::GenerateRequest rq;
  rq.kind = "respirator";
  rq.id = "onesize";
  rq.params_path = std::string(SOURCE_DIR) + "/data/generator/respirators.json";
  rq.seed = 1;
  return rq;
}

// A table at height y: a 280 mm disc of points under the head (0.3 mm of noise), as dense as the
// head's, without the points within `hidden_radius_mm` of the neck's axis (the neck hides them).
std::vector<ScanPoint> table_points(double y, double hidden_radius_mm) {
  generator::Rng rng{8};
  std::vector<ScanPoint> pn;
  for (int i = 0; i < 22000; ++i) {
    const double r = 140 * std::sqrt(rng.uniform()), a = 2 * M_PI * rng.uniform();
    if (r < hidden_radius_mm) continue;
    pn.push_back({pipeline::Point(r * std::cos(a), y + 0.3 * rng.normal(), -50 + r * std::sin(a)), pipeline::Vector(0, 0, 0)});
  }
  return pn;
}

std::size_t points_below(const std::vector<ScanPoint>& pn, double y) {
  std::size_t n = 0;
  for (const auto& p : pn) n += p.first.y() < y;
  return n;
}

}  // namespace

// No table: the neck cap is a plane at the edge of the scan, but inside the head's footprint.
TEST(remove_support_plane, a_head_that_stood_on_nothing_keeps_every_point_and_its_neck_cap) {
  auto pn = niosh_scan_points();
  const std::size_t n = pn.size();
  const CGAL::Random before = CGAL::get_default_random();
  const scan2cad::SupportPlane s = scan2cad::remove_support_plane(pn);
  EXPECT_FALSE(s.found) << s.beyond_share;
  EXPECT_EQ(pn.size(), n);
  // the RANSAC draws from a generator of its own: Poisson, after it, draws the same numbers
  CGAL::Random after = CGAL::get_default_random(), expected = before;
  EXPECT_EQ(after.get_int(0, 1 << 30), expected.get_int(0, 1 << 30));
  // kept for the footprint test alone: the cap passes the one-side test, and none of it lies
  // beyond the head (with no share asked for beyond it, it is taken: 135 mm across)
  scan2cad::SupportPlaneOptions any_share;
  any_share.min_beyond_share = 0;
  any_share.min_outline_width_share = 0;
  const scan2cad::SupportPlane cap = scan2cad::remove_support_plane(pn, any_share);
  EXPECT_TRUE(cap.found);
  EXPECT_EQ(cap.beyond_share, 0.0);
  EXPECT_NEAR(cap.width_mm, 135, 5);
}

// 20 mm above a table: the table goes, every point of the head stays.
TEST(remove_support_plane, a_table_under_the_head_is_removed_and_the_head_kept) {
  auto pn = niosh_scan_points();
  const std::size_t head = pn.size();
  const auto plate = table_points(niosh_cap_y_mm - 20, 0);
  pn.insert(pn.end(), plate.begin(), plate.end());
  const scan2cad::SupportPlane s = scan2cad::remove_support_plane(pn);
  ASSERT_TRUE(s.found);
  EXPECT_EQ(s.points_removed, plate.size());
  EXPECT_EQ(pn.size(), head);
  EXPECT_EQ(points_below(pn, niosh_cap_y_mm - 10), 0u);
  // the plane faces the head (+y), 20 mm under its cap
  EXPECT_GT(s.plane.orthogonal_vector().y() / std::sqrt(s.plane.orthogonal_vector().squared_length()), 0.999);
  EXPECT_NEAR(-s.plane.d() / s.plane.b(), niosh_cap_y_mm - 20, 0.2);
  EXPECT_NEAR(s.width_mm, 280, 10);
  std::printf("table 20 mm under the head: %zu points removed, %.0f %% of the plane beyond the head, band %.2f mm\n",
              s.points_removed, 100 * s.beyond_share, s.removal_band_mm);
}

// Standing on the table: the neck cap lies in the table's plane and goes with it (repair closes
// the neck again); the neck's wall keeps its points above the contact band (the table's noise),
// and no point of the table is left, however near the neck.
TEST(remove_support_plane, a_head_standing_on_a_table_loses_the_table_and_its_neck_cap_only) {
  auto pn = niosh_scan_points();
  const std::size_t head = pn.size(), cap = points_below(pn, niosh_cap_y_mm + 1);
  auto plate = table_points(niosh_cap_y_mm, 72);  // the cap's farthest point is 70 mm from its middle
  for (auto& p : plate) p.second = pipeline::Vector(0, 1, 0);  // marked: remove_support_plane keeps normals with points
  pn.insert(pn.end(), plate.begin(), plate.end());
  const scan2cad::SupportPlane s = scan2cad::remove_support_plane(pn);
  ASSERT_TRUE(s.found);
  EXPECT_FALSE(s.footprint.empty());
  EXPECT_LE(s.removal_band_mm, 2.5);
  EXPECT_LE(s.contact_band_mm, 1.5);  // 4 x the noise's RMS (0.3 mm; within RANSAC's 1 mm)
  EXPECT_EQ(points_below(pn, niosh_cap_y_mm + s.contact_band_mm - 0.1), 0u);
  EXPECT_EQ(std::count_if(pn.begin(), pn.end(), [](const ScanPoint& p) { return p.second.y() == 1; }), 0);
  EXPECT_GE(pn.size(), head - cap - 100);  // the cap and the noise of the wall's foot
  std::printf("head standing on the table: %zu points removed (table %zu, cap %zu), contact band %.2f mm, "
              "%zu points of the wall's lowest %.1f mm kept\n",
              s.points_removed, plate.size(), cap, s.contact_band_mm, points_below(pn, niosh_cap_y_mm + s.removal_band_mm),
              s.removal_band_mm);
}

// A cup standing on its rim (the generated one-size cup, rim down on a 250 mm table): the rim
// keeps its points above the contact band. With the removal band everywhere it lost every point
// within 2 mm of the table, up to 3.7 mm of the rim after repair.
TEST(remove_support_plane, a_cup_standing_on_its_rim_keeps_the_rim) {
  generator::GenerateRequest rq = onesize_cup_request();
  rq.outlier_fraction = 0;
  const generator::GeneratedScan cup = generator::generate_scan(rq);
  double lowest_z_mm = 1e9, x0 = 0, y0 = 0;
  for (auto v : cup.clean_mesh.vertices()) {
    const pipeline::Point& p = cup.clean_mesh.point(v);
    lowest_z_mm = std::min(lowest_z_mm, p.z());
    x0 += p.x() / double(cup.clean_mesh.number_of_vertices());
    y0 += p.y() / double(cup.clean_mesh.number_of_vertices());
  }
  std::vector<ScanPoint> pn;
  for (const auto& p : cup.cloud.points) pn.push_back({p, pipeline::Vector(0, 0, 0)});
  const std::size_t n = pn.size();
  std::size_t rim = 0;
  for (const auto& p : pn) rim += p.first.z() < lowest_z_mm + 2 && p.first.z() > lowest_z_mm + 1.0;
  generator::Rng rng{10};
  for (int i = 0; i < 40000; ++i) {
    const double r = 125 * std::sqrt(rng.uniform()), a = 2 * M_PI * rng.uniform();
    pn.push_back({pipeline::Point(x0 + r * std::cos(a), y0 + r * std::sin(a), lowest_z_mm + 0.2 * rng.normal()),
                  pipeline::Vector(0, 0, 1)});  // marked as the table's
  }
  const scan2cad::SupportPlane s = scan2cad::remove_support_plane(pn);
  ASSERT_TRUE(s.found);
  EXPECT_FALSE(s.footprint.empty());
  EXPECT_LE(s.contact_band_mm, 1.0);  // 4 x 0.2 mm
  std::size_t rim_kept = 0, table_left = 0;
  for (const auto& p : pn) {
    const bool table = p.second.z() == 1;
    rim_kept += !table && p.first.z() < lowest_z_mm + 2 && p.first.z() > lowest_z_mm + 1.0;
    table_left += table;
  }
  EXPECT_EQ(rim_kept, rim);  // the cup's points 1-2 mm above the table
  EXPECT_EQ(table_left, 0u);
  EXPECT_GE(pn.size() + 200, n);  // nothing more than the table and the rim's lowest points
  std::printf("cup on its rim: %zu points removed (table 40000), %zu rim points 1-2 mm above it kept, contact band %.2f mm\n",
              s.points_removed, rim_kept, s.contact_band_mm);
}

// A plane alone is no support of anything (reconstruct refuses it as a flat patch); nor is any
// plane in points that fill a volume, or a sphere's.
TEST(remove_support_plane, a_plane_alone_noise_or_a_sphere_has_none) {
  auto plane = table_points(0, 0);
  EXPECT_FALSE(scan2cad::remove_support_plane(plane).found);
  generator::Rng rng{9};
  std::vector<ScanPoint> box;
  for (int i = 0; i < 20000; ++i)
    box.push_back({pipeline::Point(150 * rng.uniform(), 200 * rng.uniform(), 250 * rng.uniform()), pipeline::Vector(0, 0, 0)});
  EXPECT_FALSE(scan2cad::remove_support_plane(box).found);
  generator::ScanOptions so;
  so.points = 20000;
  so.noise_mm = 0.3;
  std::vector<ScanPoint> sphere;
  for (const auto& p : generator::scan_surface(generator::triangles_of(test_meshes::sphere_soup(50, 60)), so, rng).points)
    sphere.push_back({p, pipeline::Vector(0, 0, 0)});
  EXPECT_FALSE(scan2cad::remove_support_plane(sphere).found);
}

// A generated cup has a flat part 63 mm across, the plane RANSAC finds first (its inner sheet lies
// within the removal band). The cup lies on one side of it and no other point of the cup projects
// onto it, but it lies inside the cup's outline. Judged by the nearest projected point instead of
// the outline, it was taken for a table and 14,433 of the cup's points were removed.
TEST(remove_support_plane, a_cups_flat_front_is_kept) {
  generator::GenerateRequest rq = onesize_cup_request();
  std::vector<ScanPoint> pn;
  for (const auto& p : generator::generate_scan(rq).cloud.points) pn.push_back({p, pipeline::Vector(0, 0, 0)});
  const std::size_t n = pn.size();
  scan2cad::SupportPlaneOptions any_share;
  any_share.min_beyond_share = 0;
  any_share.min_outline_width_share = 0;
  auto copy = pn;
  const scan2cad::SupportPlane front = scan2cad::remove_support_plane(copy, any_share);
  std::printf("cup: plane %.1f mm across, normal (%.2f %.2f %.2f), %.0f %% beyond\n", front.width_mm,
              front.plane.a(), front.plane.b(), front.plane.c(), 100 * front.beyond_share);
  EXPECT_TRUE(front.found);
  EXPECT_LT(front.beyond_share, 0.05);
  EXPECT_FALSE(scan2cad::remove_support_plane(pn).found);
  EXPECT_EQ(pn.size(), n);
}

// A scanner's own mesh may hold the table too, and meshes pass through reconstruct: repair
// removes the table's faces first. NIOSH medium standing on a 280 mm table meshed in 2 mm
// squares (none under the neck cap, which the head hides): the table and the cap go, and repair
// closes the neck with a faired dome (11.5 mm below the cap at 1.5 mm edges); the head alone
// loses nothing.
TEST(remove_support_plane, repair_removes_a_table_meshed_with_the_head) {
  pipeline::PolygonSoup soup = pipeline::read_scan(niosh_medium_stl).soup;
  scan2cad::RepairOptions opt;
  opt.target_edge_mm = 3.0;  // coarser than the default 1.5 mm: the test is about the table
  scan2cad::RepairReport alone;
  scan2cad::repair(soup, scan2cad::ScanKind::head, opt, &alone);
  EXPECT_EQ(alone.support_faces_removed, 0u);

  const std::size_t head_faces = soup.polygons.size(), first = soup.points.size();
  const double h = 2.0;
  const int n = 141;  // 280 mm / 2 mm + 1 points a side
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) soup.points.push_back(pipeline::Point(-140 + h * i, niosh_cap_y_mm, -190 + h * j));
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      const double x = -140 + h * (i + 0.5), z = -190 + h * (j + 0.5), r = std::hypot(x, z + 50);
      if (r < 72 || r > 140) continue;
      const std::size_t a = first + std::size_t(i * n + j), b = a + std::size_t(n);
      soup.polygons.push_back({a, b, b + 1});
      soup.polygons.push_back({a, b + 1, a + 1});
    }
  const std::size_t table_faces = soup.polygons.size() - head_faces;
  scan2cad::RepairReport on_table;
  const auto mesh = scan2cad::repair(soup, scan2cad::ScanKind::head, opt, &on_table);
  EXPECT_TRUE(on_table.closed);
  EXPECT_GE(on_table.support_faces_removed, table_faces);
  EXPECT_LE(on_table.support_faces_removed, table_faces + 1000);  // and the cap's ~600 faces
  double lowest_y_mm = 0;
  for (auto v : mesh.vertices()) lowest_y_mm = std::min(lowest_y_mm, mesh.point(v).y());
  EXPECT_GT(lowest_y_mm, niosh_cap_y_mm - 20);  // no table left: it spread 140 mm sideways, flat
  std::printf("repair: %zu of the table's %zu faces and the cap's removed, lowest point %.1f mm (cap %.1f)\n",
              on_table.support_faces_removed, table_faces, lowest_y_mm, niosh_cap_y_mm);
}

// The outline and footprint tests' distance: 0 inside a convex polygon, else to its nearest edge;
// a footprint of one point or a segment has no inside; none is infinitely far.
TEST(remove_support_plane, distance_outside_a_convex_polygon) {
  using P2 = pipeline::Kernel::Point_2;
  const std::vector<P2> square = {P2(0, 0), P2(10, 0), P2(10, 10), P2(0, 10)};  // counterclockwise
  EXPECT_EQ(scan2cad::distance_outside_convex_polygon(P2(5, 5), square), 0.0);
  EXPECT_EQ(scan2cad::distance_outside_convex_polygon(P2(10, 3), square), 0.0);  // on an edge
  EXPECT_DOUBLE_EQ(scan2cad::distance_outside_convex_polygon(P2(13, 5), square), 3.0);
  EXPECT_DOUBLE_EQ(scan2cad::distance_outside_convex_polygon(P2(13, 14), square), 5.0);  // to the corner
  EXPECT_DOUBLE_EQ(scan2cad::distance_outside_convex_polygon(P2(3, 4), {P2(0, 0)}), 5.0);
  EXPECT_DOUBLE_EQ(scan2cad::distance_outside_convex_polygon(P2(5, 2), {P2(0, 0), P2(10, 0)}), 2.0);
  EXPECT_TRUE(std::isinf(scan2cad::distance_outside_convex_polygon(P2(0, 0), {})));
}
