#pragma once
/// Geometric queries of the layering stage that CGAL answers (kept in one translation unit because
/// CGAL compiles slowly): ray casts against a triangle set and triangle-soup self-intersection.
#include <Eigen/Core>

#include <array>
#include <limits>
#include <utility>
#include <vector>

namespace layering::internal {

using Tri = std::array<int, 3>;

/// For each query i, distance [mm] along the unit ray dirs[i] from nodes[origins[i]] to the first
/// triangle of `tris` not incident to that node; +inf when the ray leaves without a hit.
std::vector<double> ray_hit_distances(const std::vector<Eigen::Vector3d>& nodes, const std::vector<Tri>& tris,
                                      const std::vector<int>& origins, const std::vector<Eigen::Vector3d>& dirs);

/// Index pairs (i, j) of triangles of the soup that intersect other than through their shared
/// nodes. Triangles sharing an edge are not tested (a fold across a shared edge shows up as a
/// negative scaled Jacobian instead); sharing one node, the opposite edges are tested; otherwise
/// CGAL's exact-predicate triangle–triangle test is used.
std::vector<std::pair<int, int>> intersecting_triangles(const std::vector<Eigen::Vector3d>& nodes,
                                                        const std::vector<Tri>& tris);

}  // namespace layering::internal
