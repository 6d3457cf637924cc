#pragma once
/// CGAL AABB-tree queries used by assemble and straps (one translation unit: CGAL compiles slowly).
#include <Eigen/Core>

#include <array>
#include <memory>
#include <vector>

namespace meshing::internal {

/// A triangle set with an AABB tree for distance and ray queries. Triangles must be oriented
/// outward for signed distances.
class TriangleTree {
 public:
  TriangleTree(const std::vector<Eigen::Vector3d>& nodes, const std::vector<std::array<int, 3>>& tris);
  ~TriangleTree();
  /// Distance [mm] to the closest triangle, negative inside: the sign is that of (q − closest) against
  /// the angle-weighted pseudo-normal of the face, edge or vertex the closest point lies on (exact on
  /// a consistently oriented manifold surface; *normal is the closest face's normal).
  double signed_distance(const Eigen::Vector3d& q, Eigen::Vector3d* closest = nullptr,
                         Eigen::Vector3d* normal = nullptr) const;
  double distance(const Eigen::Vector3d& q) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace meshing::internal
