#pragma once
// A scan of a thin part for the scan2cad tests: a closed disc 50 mm across and `thickness_mm`
// thick with a rounded rim (half a torus), like an ear's ridge of 2-3 mm seen from close by.
#include <cmath>
#include <vector>

#include "data/generator/random.h"
#include "scan2cad/internal/point_set_steps.h"

namespace test_meshes {

struct DiscScan {
  /// scanned points (noise along the true normal) with jet normals of either sign
  std::vector<scan2cad::internal::PointWithNormal> pn;
  std::vector<pipeline::Vector> outward;  ///< the true outward normal of each point
};

/// Sampled like a 200,000-point head scan (1.2 points per mm², Gaussian noise of 0.2 mm along
/// the normal); jet normals over 24 neighbours, as reconstruct estimates them.
inline DiscScan disc_scan(double thickness_mm) {
  using pipeline::Point;
  using pipeline::Vector;
  generator::Rng rng{9};
  DiscScan s;
  const double big = 25.0, r = thickness_mm / 2, pi = std::acos(-1.0);
  auto add = [&](const Point& p, const Vector& n) {
    s.pn.push_back({p + 0.2 * rng.normal() * n, Vector(0, 0, 1)});
    s.outward.push_back(n);
  };
  const double density = 1.2;
  for (int side : {-1, 1})
    for (auto i = std::size_t(density * pi * big * big); i > 0; --i) {
      const double rho = big * std::sqrt(rng.uniform()), phi = rng.uniform(0, 2 * pi);
      add(Point(rho * std::cos(phi), rho * std::sin(phi), side * r), Vector(0, 0, side));
    }
  for (auto i = std::size_t(density * 2 * pi * big * pi * r); i > 0; --i) {
    const double phi = rng.uniform(0, 2 * pi), theta = std::asin(rng.uniform(-1, 1));  // area-uniform enough
    const Vector n(std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi), std::sin(theta));
    add(Point(big * std::cos(phi), big * std::sin(phi), 0) + r * n, n);
  }
  scan2cad::internal::jet_normals(s.pn, 24);
  return s;
}

}  // namespace test_meshes
