// refit_on_own_side: the two sides of a thin part, pulled together by jet smoothing over both,
// get their places back; a surface with one side in reach is left as it was.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdio>

#include "data/generator/random.h"
#include "data/generator/scanner_artifacts.h"
#include "scan2cad/internal/point_set_steps.h"
#include "scan2cad/internal/refit_on_own_side.h"
#include "test_meshes.h"
#include "thin_disc_scan.h"

namespace {

using scan2cad::internal::PointWithNormal;
using pipeline::Point;
using pipeline::Vector;

// Mean |z| of the points of the two flat faces at least 5 mm inside the rim: half the
// thickness where the faces are where they should be.
double mean_half_thickness(const std::vector<PointWithNormal>& pn) {
  double sum = 0;
  std::size_t n = 0;
  for (const auto& [p, normal] : pn)
    if (p.x() * p.x() + p.y() * p.y() < 20.0 * 20.0) sum += std::abs(p.z()), ++n;
  return sum / double(n);
}

// Share of the points of the flat faces whose normal is within 10 deg of the face's own (±z).
double share_of_normals_within_10deg(const std::vector<PointWithNormal>& pn) {
  std::size_t n = 0, right = 0;
  for (const auto& [p, normal] : pn) {
    if (p.x() * p.x() + p.y() * p.y() >= 20.0 * 20.0) continue;
    ++n;
    right += normal.z() * (p.z() > 0 ? 1 : -1) > std::cos(10 * std::acos(-1.0) / 180);
  }
  return double(right) / double(n);
}

// The scan as reconstruct has it when the refit starts: jet-smoothed over plain neighbourhoods,
// jet normals of the smoothed points, oriented (here by the true normals, so the test sees the
// refit alone), and the unsmoothed positions beside them.
struct Smoothed {
  std::vector<PointWithNormal> pn;
  std::vector<Point> raw;
};
Smoothed smoothed_and_oriented(std::vector<PointWithNormal> pn, const std::vector<Vector>& outward) {
  Smoothed s;
  for (const auto& x : pn) s.raw.push_back(x.first);
  scan2cad::internal::jet_smooth(pn, 24);
  scan2cad::internal::jet_normals(pn, 24);
  for (std::size_t i = 0; i < pn.size(); ++i)
    if (pn[i].second * outward[i] < 0) pn[i].second = -pn[i].second;
  s.pn = std::move(pn);
  return s;
}

}  // namespace

// A disc 2.5 mm thick, 0.2 mm noise: 24 neighbours (radius ~2.5 mm) reach the other face from
// most places on a face. Measured: CGAL's smoothing pulls each face 0.25 mm toward the middle
// (mean |z| 1.002 mm where the scan's is 1.253) and leaves 28.8 % of the face normals within
// 10 deg of the face's; after the refit 1.237 mm and 83.1 %. Bounds: the refit within 0.06 mm of
// the scan (3,600 refitted points of 0.2 mm noise average to ~0.004 mm; what is left is the jet's
// bias near the rim), the smoothing at least 0.2 mm off, and the normals' shares apart by more
// than the two measured figures' half-distance.
TEST(refit_on_own_side, brings_back_the_two_faces_of_a_thin_disc) {
  const test_meshes::DiscScan disc = test_meshes::disc_scan(2.5);
  Smoothed s = smoothed_and_oriented(disc.pn, disc.outward);
  const double raw_half = [&] {
    std::vector<PointWithNormal> r;
    for (const Point& p : s.raw) r.push_back({p, Vector(0, 0, 1)});
    return mean_half_thickness(r);
  }();
  const double smoothed_half = mean_half_thickness(s.pn), smoothed_share = share_of_normals_within_10deg(s.pn);
  std::vector<char> thin;
  const auto st = scan2cad::internal::refit_on_own_side(s.pn, s.raw, 24, 0.5, &thin);
  const double refit_half = mean_half_thickness(s.pn), refit_share = share_of_normals_within_10deg(s.pn);
  std::printf("half thickness: scan %.3f, smoothed %.3f, refitted %.3f mm; normals within 10 deg: %.1f %% -> %.1f %%; "
              "%zu one-sided, %zu refitted, %zu too few, %zu spikes\n",
              raw_half, smoothed_half, refit_half, 100 * smoothed_share, 100 * refit_share, st.one_sided, st.refitted,
              st.too_few, st.spikes);
  EXPECT_LT(smoothed_half, raw_half - 0.2);
  EXPECT_NEAR(refit_half, raw_half, 0.06);
  EXPECT_LT(smoothed_share, 0.5);
  EXPECT_GT(refit_share, 0.6);
  EXPECT_GT(st.refitted, st.one_sided);
  EXPECT_EQ(st.spikes, 0u);
  // the thin-part flags (reconstruct gives those points to Poisson unthinned): one per point
  // returned, set for the refitted and the too-few ones
  ASSERT_EQ(thin.size(), s.pn.size());
  EXPECT_EQ(std::size_t(std::count(thin.begin(), thin.end(), 1)), st.refitted + st.too_few);
}

// A sphere 80 mm across has one side in every neighbourhood: nothing moves, no point is dropped.
TEST(refit_on_own_side, leaves_a_surface_with_one_side_in_reach_as_it_is) {
  generator::Rng rng{5};
  generator::ScanOptions so;
  so.points = 20000;
  so.noise_mm = 0.2;
  so.outliers.fraction = 0;  // an outlier's neighbours would face it from all sides
  const auto cloud = generator::scan_surface(generator::triangles_of(test_meshes::sphere_soup(40, 60)), so, rng);
  std::vector<PointWithNormal> pn;
  std::vector<Vector> outward;
  for (const Point& p : cloud.points) {
    pn.push_back({p, Vector(0, 0, 1)});
    outward.push_back(p - CGAL::ORIGIN);
  }
  Smoothed s = smoothed_and_oriented(pn, outward);
  const std::vector<PointWithNormal> before = s.pn;
  std::vector<char> thin;
  const auto st = scan2cad::internal::refit_on_own_side(s.pn, s.raw, 24, 0.5, &thin);
  EXPECT_EQ(st.one_sided, before.size());
  EXPECT_EQ(thin, std::vector<char>(before.size(), 0));
  ASSERT_EQ(s.pn.size(), before.size());
  for (std::size_t i = 0; i < before.size(); ++i) {
    ASSERT_EQ(s.pn[i].first, before[i].first) << i;
    ASSERT_EQ(s.pn[i].second, before[i].second) << i;
  }
}

// The refit drops its spikes from the unsmoothed positions as well as from the points, so
// raw[i] still goes with pn[i] on return (reconstruct then projects Poisson's vertices onto the
// unsmoothed points with the denoised points' normals). A disc point's unsmoothed position
// lifted 3 mm off its face is a spike: it must go, and every other pair must stay paired.
TEST(refit_on_own_side, drops_a_spike_from_the_unsmoothed_positions_too) {
  const test_meshes::DiscScan disc = test_meshes::disc_scan(2.5);
  Smoothed s = smoothed_and_oriented(disc.pn, disc.outward);
  std::size_t spike = 0;  // the point nearest the top face's centre
  for (std::size_t i = 0; i < s.raw.size(); ++i)
    if (s.pn[i].second.z() > 0 && CGAL::squared_distance(s.raw[i], Point(0, 0, 1.25)) <
                                      CGAL::squared_distance(s.raw[spike], Point(0, 0, 1.25)))
      spike = i;
  s.raw[spike] = s.raw[spike] + Vector(0, 0, 3.0);
  const Point spike_at = s.raw[spike];
  std::vector<Point> raw_others;  // the unsmoothed positions of the other points, in order
  for (std::size_t i = 0; i < s.raw.size(); ++i)
    if (i != spike) raw_others.push_back(s.raw[i]);
  const auto st = scan2cad::internal::refit_on_own_side(s.pn, s.raw, 24, 0.5);
  EXPECT_EQ(st.spikes, 1u);  // the disc's own points: none (brings_back_the_two_faces_of_a_thin_disc)
  ASSERT_EQ(s.raw.size(), s.pn.size());
  EXPECT_EQ(std::count(s.raw.begin(), s.raw.end(), spike_at), 0);
  EXPECT_EQ(s.raw, raw_others);
}
