#pragma once
/// Internal to scan2cad/align: surface sampling and reflective-symmetry plane detection.
///
/// Why by hand: CGAL has no reflective-symmetry detector. We use CGAL's AABB tree for the
/// closest-point queries and Eigen for the small linear solves; the search itself (candidate
/// planes + reflect-and-match point-to-plane ICP) is written here.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "pipeline/surface_mesh.h"

namespace scan2cad::internal {

/// Points spread uniformly (by area) over a surface [mm], with the unit normal of their face.
struct SurfaceSamples {
  std::vector<Eigen::Vector3d> p;  ///< #S positions [mm]
  std::vector<Eigen::Vector3d> n;  ///< #S unit face normals (outward if the mesh is oriented)
};

/// Area-uniform random samples (fixed seed: deterministic). Degenerate faces are skipped.
/// @throws pipeline::Error(bad_input) if the mesh has no face of positive area.
SurfaceSamples sample_surface(const pipeline::SurfaceMesh& mesh, std::size_t count, unsigned seed = 7);

/// Mean and covariance (3×3) of samples [mm, mm²]; with area-uniform samples these are the
/// surface's area-weighted centroid and second moments.
void sample_moments(const SurfaceSamples& s, Eigen::Vector3d& mean, Eigen::Matrix3d& cov);

/// A plane {x : n·x = d}, |n| = 1 [d in mm].
struct Plane {
  Eigen::Vector3d n = Eigen::Vector3d::UnitX();
  double d = 0.0;
};

struct SymmetryResult {
  Plane plane;
  double rms_mm = 0.0;           ///< RMS point-to-surface distance of the reflected inliers
  double inlier_fraction = 0.0;  ///< share of samples whose mirror image lies near the surface
};

/// Distances [mm] from `queries` to the surface, capped: min(distance, cap_mm), by the bounded
/// closest-point queries of the symmetry search (a box test, then CGAL's hinted exact query).
/// With `seed_with_previous`, each query is seeded with the previous query's match, as the ICP
/// seeds a sample's query with its last match. Exposed so a test can compare it with plain
/// unbounded CGAL queries.
std::vector<double> capped_distances(const pipeline::SurfaceMesh& mesh, const std::vector<Eigen::Vector3d>& queries,
                                     double cap_mm, bool seed_with_previous = false);

/// Finds the plane of best reflective symmetry of a closed or open surface.
/// Candidates: the 3 principal axes and 150 directions over a hemisphere, each through the area
/// centroid, scored by the truncated mean distance of reflected samples to the surface; the best
/// 3 distinct candidates are refined by reflect-and-match point-to-plane ICP on ~500 samples,
/// and the most symmetric of them is refined again on every k-th sample, k = ⌊samples / 2500⌋
/// (all the default 4000; 2500-4999 of any larger number).
/// @throws pipeline::Error(algorithm) if no candidate converges to a plane with inliers.
SymmetryResult find_symmetry_plane(const pipeline::SurfaceMesh& mesh, std::size_t samples = 4000);

}  // namespace scan2cad::internal
