#pragma once
/// Internal to scan2cad/reconstruct: CGAL's per-point point-set steps on both cores.
///
/// Each function gives exactly what the CGAL function named beside it gives with
/// CGAL::Sequential_tag (the same per-point code of CGAL 5.5's Point_set_processing_3, on the same
/// k-d tree and neighbours, results combined in the same order), but runs the points on all
/// OpenMP threads with a static schedule. Why not CGAL's Parallel_tag: it runs them through TBB,
/// whose work stealing hands the points to the threads differently in every run, so the main
/// thread's heap history changes from run to run, and with it the result of Poisson's Delaunay
/// refinement, whose order follows heap addresses (two 1M-point runs with TBB: 202,856 and
/// 202,738 faces). With a static schedule every thread does the same points in every run.
/// The per-point kernels are CGAL's own (namespace CGAL::internal), not re-implemented.
#include <utility>
#include <vector>

#include <CGAL/Point_set_processing_3/internal/Neighbor_query.h>
#include <CGAL/property_map.h>

#include "pipeline/surface_mesh.h"

namespace scan2cad::internal {

using PointWithNormal = std::pair<pipeline::Point, pipeline::Vector>;

/// The point of a point-with-normal, as CGAL's point-set functions read it.
using PointWithNormalPointMap = CGAL::First_of_pair_property_map<PointWithNormal>;

/// CGAL's k-nearest query over the points of a point-with-normal vector, as its point-set
/// functions build it; the per-point kernels below and refit_on_own_side take it.
using PointNeighborQuery =
    CGAL::Point_set_processing_3::internal::Neighbor_query<pipeline::Kernel, const std::vector<PointWithNormal>&,
                                                           PointWithNormalPointMap>;

/// CGAL's default degrees of jet_smooth_point_set and jet_estimate_normals (fitting, Monge).
constexpr unsigned jet_degree_fitting = 2, jet_degree_monge = 2;

/// CGAL::compute_average_spacing(points, k): mean over the points of the mean distance to their
/// k nearest points [mm].
double average_spacing(const std::vector<PointWithNormal>& pn, unsigned k);

/// CGAL::remove_outliers(points, k, threshold_percent(100).threshold_distance(d)) followed by the
/// erase of the outliers: keeps the points whose mean squared distance to their k nearest is below
/// d², in the order CGAL leaves them. Returns the number removed.
std::size_t remove_far_points(std::vector<PointWithNormal>& pn, unsigned k, double threshold_distance_mm);

/// remove_far_points(pn, k, factor × average_spacing(pn, k)), bit for bit, with one k-nearest
/// query per point instead of two: both means are taken over the same neighbours, in the same
/// order. Returns the number removed.
std::size_t remove_points_beyond_spacing(std::vector<PointWithNormal>& pn, unsigned k, double factor);

/// CGAL::jet_smooth_point_set(points, k): each point projected onto the quadric jet of its k
/// nearest points (all fitted on the unsmoothed positions); the normals are left as they are.
void jet_smooth(std::vector<PointWithNormal>& pn, unsigned k);

/// CGAL::jet_estimate_normals(points, k): unoriented unit normals of the quadric jets.
void jet_normals(std::vector<PointWithNormal>& pn, unsigned k);

/// Not a CGAL step: the share of up to `samples` evenly spread points whose own normal lies within
/// 45 deg (either sign) of the normal of their k-nearest quadric jet. A scanner's normals follow its
/// surface nearly everywhere; normals all (0, 0, 1) do on ~30 % of a head.
double share_of_normals_along_surface(const std::vector<PointWithNormal>& pn, unsigned k, std::size_t samples);

/// Not a CGAL step: the share of up to `samples` evenly spread points whose k nearest points fit a
/// plane with a quality of at least `min_quality`, the quality CGAL's linear_least_squares_fitting_3
/// gives: 1 − λmin/λmid of their covariance (1 on a plane, 0 when they spread alike in every
/// direction). Tells a scanned surface from points that fill a volume.
double share_of_points_on_a_surface(const std::vector<PointWithNormal>& pn, unsigned k, std::size_t samples,
                                    double min_quality);

/// The least spike_move_limit_mm gives [mm]: a structured-light scanner's accuracy (0.05-0.1 mm).
/// Points sampled from a CAD model or a mesh move 0 onto their jets wherever the surface is a
/// quadric, and without a floor the limit was 0: a noise-free drum lost all of its curved side as
/// "spikes" and reconstruct refused the rest as a scan in pieces (sweep S).
constexpr double min_spike_move_mm = 0.1;

/// Not a CGAL step: the move [mm] above which a jet projection calls its point a spike, 4 robust
/// standard deviations (1.4826 × the median) of `moves_mm`, the points' moves onto their jets,
/// and at least min_spike_move_mm. Infinite when there are no moves. Shared by reconstruct's
/// smoothing and the own-side refit.
double spike_move_limit_mm(std::vector<double> moves_mm);

}  // namespace scan2cad::internal
