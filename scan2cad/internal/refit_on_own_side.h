#pragma once
/// Internal to scan2cad/reconstruct: jet smoothing and normals again, once the normals are
/// oriented, with each point's neighbourhood limited to its own side of the surface.
///
/// Before orientation a neighbourhood cannot tell the two sides of a thin part apart: on an
/// ear's ridge 2-3 mm wide, a point's 24 nearest points (radius ~2.7 mm at a 200,000-point scan)
/// include the other side, so CGAL's jet smoothing pulls both sides toward the middle and the
/// jet normals tilt; Poisson and the projection onto the points then cut the ridge's top off
/// (NIOSH large: 3.15 mm; with the true normals and no smoothing 1.44 mm, scan2cad/README.md).
/// Once oriented, the other side's normals point the other way. Here each point that has such a
/// point (n_i . n_j < 0) among its k nearest is fitted again from its unsmoothed position: CGAL's
/// jet (Monge_via_jet_fitting, the degrees of jet_smooth_point_set) over its k nearest of 2k
/// unsmoothed candidates whose oriented normal agrees with its own (n_i . n_j > min_cos); the
/// point moves onto the jet and takes the jet's normal, with its old sign. The other points keep
/// CGAL's smoothing (refitting them too moved the generated heads' maxima under the nose toward
/// 1 mm). CGAL's smoothing takes a plain k-NN neighbourhood, hence this step; the k-NN searches
/// run on all OpenMP threads (static schedule: the same result every run).
#include <cstddef>
#include <utility>
#include <vector>

#include "pipeline/surface_mesh.h"

namespace scan2cad::internal {

/// What refit_on_own_side did.
struct RefitStats {
  std::size_t one_sided = 0;   ///< points left as they were: no other side among their k nearest
  std::size_t refitted = 0;    ///< points moved onto their own side's jet
  std::size_t too_few = 0;     ///< points left as they were: fewer than max(6, k/2) agreeing neighbours
  std::size_t spikes = 0;      ///< points dropped: the jet moved them by more than 4 robust sigma
};

/// @param[in,out] pn   oriented points [mm] with unit normals (smoothed positions); on return the
///                     refitted points, spikes dropped, order kept
/// @param[in,out] raw  the same points' unsmoothed positions, raw[i] for pn[i]
///                     (@throws std::invalid_argument if the sizes differ); on return the
///                     spikes are dropped here too, so raw[i] still goes with pn[i]
/// @param[in]     k    neighbours of a fit (≥ 6)
/// @param[in]     min_cos  a neighbour is on the point's side when n_i . n_j > min_cos
/// @param[out]    thin  optional: on return one flag per returned point, 1 for the points that
///                     have the other side among their k nearest (refitted or kept for too few
///                     on their side), 0 for the others
/// Spikes are dropped as by jet smoothing in reconstruct (spike_move_limit_mm of the refitted
/// points' moves, point_set_steps.h).
RefitStats refit_on_own_side(std::vector<std::pair<pipeline::Point, pipeline::Vector>>& pn,
                             std::vector<pipeline::Point>& raw, unsigned k, double min_cos,
                             std::vector<char>* thin = nullptr);

}  // namespace scan2cad::internal
