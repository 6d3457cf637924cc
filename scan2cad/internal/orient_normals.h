#pragma once
/// Internal to scan2cad/reconstruct: normal orientation by a minimum spanning tree that does not
/// propagate across thin parts of the surface.
///
/// CGAL::mst_orient_normals (Hoppe et al. 1992) links each point to its k nearest neighbours,
/// weighs a link 1 - |n_i . n_j| and carries the top point's orientation along the minimum
/// spanning tree. Where the surface is thinner than a neighbourhood (an ear's ridge or slot,
/// 1.5-3 mm across, point spacing 0.9 mm), a point's neighbours include points of the other side,
/// whose unoriented normals are parallel to its own: such a link costs nothing, the tree crosses
/// there, and the other side gets the wrong orientation. Measured on the NIOSH large headform
/// (reconstruct + repair; scan2cad/README.md): at 150,000 points repair failed, at 210,000 and
/// 300,000 points and at 200,000 with another seed the ears were 4.5-9.9 mm off.
///
/// Here a link also costs how far it leaves the tangent planes, max(|n_i . e|, |n_j . e|) with e
/// the unit link direction, times `crossing_weight`: a link between two sides runs along the
/// normals (cost ~1), one within a side runs in the tangent plane (cost ~0). Everything else is
/// CGAL's own code (its Riemannian graph type, its create_mst_graph and orientation visitor); with
/// crossing_weight = 0 the result is exactly CGAL::mst_orient_normals' (tested). The neighbour
/// searches run on all OpenMP threads (static schedule, same result every run).
#include <cstddef>
#include <utility>
#include <vector>

#include "pipeline/surface_mesh.h"

namespace scan2cad::internal {

/// Orients the unit normals of `pn` and drops the points the tree cannot reach (as CGAL does).
///
/// @param[in,out] pn  points [mm] with unit normals of any sign; on return the oriented points,
///                    in CGAL::mst_orient_normals' order (the reached ones, in input order)
/// @param[in]     k   neighbours per point (≥ 2)
/// @param[in]     crossing_weight  cost of a link running along the normals; 0 = CGAL's weights
/// @param[out]    reached  if given, the input index of each point kept, in order
/// @return the number of points dropped
std::size_t orient_normals(std::vector<std::pair<pipeline::Point, pipeline::Vector>>& pn, unsigned k,
                           double crossing_weight, std::vector<std::size_t>* reached = nullptr);

}  // namespace scan2cad::internal
