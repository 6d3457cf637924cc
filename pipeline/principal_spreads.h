#pragma once
/// principal_spreads: how far a set of points spreads along its three principal axes, to tell a
/// surface that encloses or bends around something from one on a plane or a line.
///
/// Input:  any range of items and a function giving each item's point (p[0..2]: CGAL points,
///         Eigen vectors) [mm].
/// Output: the standard deviations along the principal axes [mm], smallest first; zeros for
///         no items.
/// Shared by reconstruct (its points) and repair (a mesh's vertices): both refuse a flat patch,
/// on which CGAL's Poisson never finishes and repair's smoothing gave NaN.
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cstdio>
#include <string>

namespace pipeline {

template <class Range, class PointOf>
Eigen::Vector3d principal_spreads(const Range& items, PointOf point_of) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  double n = 0;
  for (const auto& item : items) {
    const auto& p = point_of(item);
    mean += Eigen::Vector3d(double(p[0]), double(p[1]), double(p[2]));
    n += 1;
  }
  if (n == 0) return Eigen::Vector3d::Zero();
  mean /= n;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& item : items) {
    const auto& p = point_of(item);
    const Eigen::Vector3d d = Eigen::Vector3d(double(p[0]), double(p[1]), double(p[2])) - mean;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov / n);
  return eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();  // ascending
}

/// The thinnest a head or a respirator spreads across its thinnest principal axis, as a share of
/// its longest: NIOSH medium 0.64, a generated cup 0.48; a noisy plane is under a fiftieth.
inline constexpr double min_thickness_share = 0.02;

/// "" when `spreads_mm` (principal_spreads) are a head's or a respirator's, else why not, for a
/// bad-input line; `what` names the items ("the points", "the surface").
inline std::string why_flat(const Eigen::Vector3d& spreads_mm, const std::string& what) {
  if (spreads_mm[0] >= min_thickness_share * spreads_mm[2]) return "";
  char spread[120];
  std::snprintf(spread, sizeof spread, "(spread %.3f mm across it, %.1f mm along it)", spreads_mm[0], spreads_mm[2]);
  return what + " lie on a plane or a line " + spread + ": a flat patch, not a head or a respirator";
}

}  // namespace pipeline
