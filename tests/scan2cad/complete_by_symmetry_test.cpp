// complete_fills_by_symmetry on a sphere with mirror-symmetric dents: a hole cut over one dent is
// faired flat by fill_holes and gets its dent back from the mirror image of the other one.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include "scan2cad/complete_by_symmetry.h"
#include "scan2cad/fill_holes.h"
#include "test_meshes.h"

namespace {

using pipeline::Point;
using pipeline::Vector;

const double kRadius = 50;  // mm

Vector unit(const Vector& v) { return v / std::sqrt(v.squared_length()); }

double gaussian(const Vector& dir, const Vector& centre, double sigma_mm) {
  const double d2 = (dir - centre).squared_length() * kRadius * kRadius;
  return std::exp(-d2 / (2 * sigma_mm * sigma_mm));
}

// Radius [mm] in direction `dir` (unit): an egg that is mirror symmetric about x = 0 only (a
// sphere would be symmetric about every plane through its centre, and the symmetry detector
// could pick any), with two dents 4 mm deep at (±0.5, 0.4, z), mirror images of each other.
// `extra` adds an asymmetric part.
double dented_radius(const Vector& dir, const std::function<double(const Vector&)>& extra) {
  const Vector right = unit(Vector(0.5, 0.4, 0.768)), left = unit(Vector(-0.5, 0.4, 0.768));
  const Vector a(0, 0.8, 0.6), b(0, 0.6, -0.8);
  const double egg = 1.0 + 0.25 * (dir * a) + 0.2 * dir.x() * dir.x() + 0.15 * std::pow(dir * b, 3);
  return kRadius * egg - 4.0 * gaussian(dir, right, 5.0) - 4.0 * gaussian(dir, left, 5.0) +
         (extra ? extra(dir) : 0.0);
}

pipeline::SurfaceMesh dented_sphere(const std::function<double(const Vector&)>& extra = {}) {
  auto soup = test_meshes::sphere_soup(kRadius, 90);  // edges ≈ 1.7 mm
  for (auto& p : soup.points) {
    const Vector dir = unit(p - CGAL::ORIGIN);
    p = CGAL::ORIGIN + dented_radius(dir, extra) * dir;
  }
  return test_meshes::mesh_of(soup);
}

// Largest radial error of the vertices within `radius` of `centre` [mm].
double worst_error_near(const pipeline::SurfaceMesh& m, const Point& centre, double radius,
                        const std::function<double(const Vector&)>& extra = {}) {
  double worst = 0;
  for (auto v : m.vertices()) {
    const Point& p = m.point(v);
    if (CGAL::squared_distance(p, centre) > radius * radius) continue;
    const Vector r = p - CGAL::ORIGIN;
    worst = std::max(worst, std::abs(std::sqrt(r.squared_length()) - dented_radius(unit(r), extra)));
  }
  return worst;
}

// Removes the faces whose centroid lies within `radius` of `centre` and fills the hole.
std::vector<std::vector<pipeline::FaceIndex>> cut_and_fill(pipeline::SurfaceMesh& m, const Point& centre, double radius) {
  std::vector<pipeline::FaceIndex> cut;
  for (auto f : m.faces()) {
    Vector c(0, 0, 0);
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) c = c + (m.point(v) - CGAL::ORIGIN);
    if (CGAL::squared_distance(CGAL::ORIGIN + c / 3.0, centre) < radius * radius) cut.push_back(f);
  }
  for (auto f : cut) CGAL::Euler::remove_face(m.halfedge(f), m);
  m.collect_garbage();
  std::vector<std::vector<pipeline::FaceIndex>> fills;
  scan2cad::fill_holes(m, scan2cad::ScanKind::head, &fills);
  return fills;
}

const Vector kDentDir = unit(Vector(0.5, 0.4, 0.768));

// The surface point in direction `dir`.
Point surface_point(const Vector& dir, const std::function<double(const Vector&)>& extra = {}) {
  return CGAL::ORIGIN + dented_radius(unit(dir), extra) * unit(dir);
}

const Point kDentCentre = surface_point(kDentDir);
const Vector kMidlineDir = unit(Vector(0, -0.6, 0.8));

}  // namespace

TEST(complete_by_symmetry, hole_over_a_dent_gets_the_mirrored_dent_back) {
  auto m = dented_sphere();
  auto fills = cut_and_fill(m, kDentCentre, 9.0);
  ASSERT_EQ(fills.size(), 1u);
  // fairing from the border cannot know the dent: its centre is 4 mm deep, the border sees only
  // its flank
  const double faired = worst_error_near(m, kDentCentre, 12.0);
  EXPECT_GT(faired, 1.0);
  const auto rep = scan2cad::complete_fills_by_symmetry(m, fills);
  ASSERT_TRUE(rep.plane_found) << rep.skipped;
  EXPECT_TRUE(rep.skipped.empty()) << rep.skipped;
  EXPECT_NEAR(std::abs(rep.plane_normal.x()), 1.0, 1e-3);
  ASSERT_EQ(rep.holes.size(), 1u);
  EXPECT_TRUE(rep.holes[0].completed);
  EXPECT_EQ(rep.holes[0].mirrored_vertices, rep.holes[0].fill_vertices);
  // The mirrored targets lie on the other dent's facets, whose chord error is h²/(8ρ) ≈ 0.05 mm
  // (h ≈ 2 mm edges on the egg, ρ ≈ σ²/depth ≈ 10 mm); the fill's own facets are ~1 mm. 0.2 mm leaves room
  // for the symmetry plane's fit (its RMS is printed in the report).
  const double completed = worst_error_near(m, kDentCentre, 12.0);
  std::printf("dent hole: faired %.3f mm, completed %.3f mm off; plane RMS %.3f mm\n", faired, completed,
              rep.plane_rms_mm);
  EXPECT_LT(completed, 0.2) << "faired " << faired;
  EXPECT_TRUE(CGAL::is_closed(m));
}

// A hole on the side, where the surface faces mostly along the symmetry plane's normal (x): each
// fill vertex's mirror match must face like its normal reflected, (-nx, ny, nz). Projected onto the
// plane instead, (0, ny, nz), it is ~65 deg off there, past the 60 deg allowed, and the hole was
// left faired; the dent test above, at 30 deg from the plane, passed that (sweep N).
TEST(complete_by_symmetry, hole_on_the_side_is_completed_from_its_mirror_image) {
  auto m = dented_sphere();
  const Point side = surface_point(Vector(0.9, 0.1, 0.42));
  auto fills = cut_and_fill(m, side, 9.0);
  ASSERT_EQ(fills.size(), 1u);
  const auto rep = scan2cad::complete_fills_by_symmetry(m, fills);
  ASSERT_TRUE(rep.plane_found) << rep.skipped;
  ASSERT_EQ(rep.holes.size(), 1u);
  EXPECT_TRUE(rep.holes[0].completed);
  EXPECT_EQ(rep.holes[0].mirrored_vertices, rep.holes[0].fill_vertices);
  EXPECT_LT(worst_error_near(m, side, 12.0), 0.2);
}

TEST(complete_by_symmetry, hole_whose_surroundings_are_not_symmetric_keeps_its_fairing) {
  // a 2 mm swelling only on the dented side, centred ~12 mm above the dent: the ring around the
  // hole differs from its mirror image by 0.5-2 mm, so the other side says nothing reliable there
  const Vector swelling_dir = unit(kDentDir + Vector(0, 0.24, 0));
  const auto swelling = [&](const Vector& dir) { return 2.0 * gaussian(dir, swelling_dir, 10.0); };
  auto m = dented_sphere(swelling);
  auto fills = cut_and_fill(m, surface_point(kDentDir, swelling), 9.0);
  ASSERT_EQ(fills.size(), 1u);
  const pipeline::SurfaceMesh before = m;
  const auto rep = scan2cad::complete_fills_by_symmetry(m, fills);
  ASSERT_TRUE(rep.plane_found) << rep.skipped;
  EXPECT_NEAR(std::abs(rep.plane_normal.x()), 1.0, 1e-2);
  ASSERT_EQ(rep.holes.size(), 1u);
  EXPECT_FALSE(rep.holes[0].completed);
  EXPECT_GT(rep.holes[0].ring_asymmetry_rms_mm, 0.5);
  for (auto v : m.vertices()) ASSERT_EQ(m.point(v), before.point(v));
}

TEST(complete_by_symmetry, hole_across_the_symmetry_plane_stays_continuous) {
  // A hole centred on x = 0: the mirror image of a fill vertex lies in the same fill, except
  // along the border; the result must stay as close to the surface as the fairing was (no
  // step, no blow-up).
  auto m = dented_sphere();
  const Point midline = surface_point(kMidlineDir);
  auto fills = cut_and_fill(m, midline, 7.0);
  ASSERT_EQ(fills.size(), 1u);
  const double faired = worst_error_near(m, midline, 10.0);
  const auto rep = scan2cad::complete_fills_by_symmetry(m, fills);
  ASSERT_EQ(rep.holes.size(), 1u);
  EXPECT_LT(rep.holes[0].mirrored_vertices, rep.holes[0].fill_vertices / 2);
  EXPECT_LE(worst_error_near(m, midline, 10.0), faired + 0.05) << "faired " << faired;
}

TEST(complete_by_symmetry, surface_without_fills_or_symmetry_is_left_alone) {
  auto m = dented_sphere();
  const auto none = scan2cad::complete_fills_by_symmetry(m, {});
  EXPECT_FALSE(none.skipped.empty());
  EXPECT_TRUE(none.holes.empty());
  // a strongly lopsided surface: no plane matches it well enough
  const auto lopsided = [](const Vector& dir) {
    return 12.0 * gaussian(dir, unit(Vector(0.3, 0.2, 0.9)), 20.0) + 9.0 * gaussian(dir, unit(Vector(-0.7, -0.5, 0.1)), 15.0) +
           7.0 * gaussian(dir, unit(Vector(0.1, 0.9, -0.4)), 10.0);
  };
  auto l = dented_sphere(lopsided);
  auto fills = cut_and_fill(l, surface_point(kDentDir, lopsided), 6.0);
  ASSERT_EQ(fills.size(), 1u);
  const pipeline::SurfaceMesh before = l;
  const auto rep = scan2cad::complete_fills_by_symmetry(l, fills);
  EXPECT_FALSE(rep.skipped.empty()) << "plane RMS " << rep.plane_rms_mm << " mm, inliers " << rep.plane_inliers;
  for (auto v : l.vertices()) ASSERT_EQ(l.point(v), before.point(v));
}
