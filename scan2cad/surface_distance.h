#pragma once
/// Distances between two surfaces, to judge a reconstruction against its reference.
#include <cstddef>
#include <vector>

#include "pipeline/surface_mesh.h"

namespace scan2cad {

struct SurfaceDistance {
  double hausdorff_mm = 0;    ///< symmetric: max over both directions [mm]
  double a_to_b_max_mm = 0;   ///< max over samples of a of the distance to b [mm]
  double b_to_a_max_mm = 0;
  double p95_mm = 0;          ///< 95th percentile of the pooled distances of both directions [mm]
  double mean_mm = 0;
  pipeline::Point a_worst, b_worst;  ///< samples of a and of b farthest from the other mesh [mm]
};

/// A ball [mm]: a region left out of a distance measurement (e.g. a scan hole, where the
/// output is a fill of a surface nobody saw).
struct Ball {
  pipeline::Point centre;
  double radius_mm = 0;
};

/// A half-space [mm]: the points p with (p - point) · normal > 0 (e.g. below the neck cut of a
/// headform, where the reference surface is an artificial cap, not anatomy).
struct HalfSpace {
  pipeline::Point point;
  pipeline::Vector normal;
};

/// Regions left out of one measurement: samples in any ball or any half-space.
struct Exclusion {
  std::vector<Ball> balls;
  std::vector<HalfSpace> half_spaces;
};

/// Samples `samples_per_mesh` points uniformly on each mesh (PMP::sample_triangle_mesh, plus
/// every vertex) and measures each sample's distance to the other mesh with an AABB tree.
/// The maximum over samples is the symmetric Hausdorff distance up to the sampling density.
///
/// @param[in] a, b  triangle meshes [mm], non-empty
/// @param[in] samples_per_mesh  random points per mesh; default 200,000; seed fixed
/// @param[in] excluded  samples (of either mesh) inside any of these balls are not measured
/// @throws pipeline::Error(bad_input) if either mesh has no faces or every sample is excluded
SurfaceDistance surface_distance(const pipeline::SurfaceMesh& a, const pipeline::SurfaceMesh& b,
                                 std::size_t samples_per_mesh = 200000, const std::vector<Ball>& excluded = {});

/// The same for several sets of excluded balls at the cost of one: the meshes are sampled and
/// the distances measured once, then summarised once per set (e.g. {} and the scan's holes).
/// @return one SurfaceDistance per entry of `exclusions`, in order
std::vector<SurfaceDistance> surface_distances(const pipeline::SurfaceMesh& a, const pipeline::SurfaceMesh& b,
                                               std::size_t samples_per_mesh,
                                               const std::vector<std::vector<Ball>>& exclusions);
/// The same with exclusions that may also hold half-spaces.
std::vector<SurfaceDistance> surface_distances(const pipeline::SurfaceMesh& a, const pipeline::SurfaceMesh& b,
                                               std::size_t samples_per_mesh, const std::vector<Exclusion>& exclusions);

/// How near the scan itself came to a point of the reference: the distance from `p` to the
/// nearest point of `cloud` [mm]. At a reconstruction's worst reference point this tells "the
/// method cut it off" from "the scanner never sampled it": at a tip or a thin edge, a surface
/// nearer to p than this reaches out beyond every point the scan gave.
/// A linear scan of the cloud, for a few queries (no search tree is worth building for them).
///
/// @param[in] cloud  scan points [mm], non-empty
/// @param[in] p  a point [mm], e.g. SurfaceDistance::b_worst
/// @throws pipeline::Error(bad_input) if the cloud has no points
double nearest_point_distance_mm(const pipeline::PointCloud& cloud, const pipeline::Point& p);

}  // namespace scan2cad
