// AABB-tree queries (CGAL) behind meshing::internal::TriangleTree.
#include "meshing/internal/assemble_geometry.h"

#include <Eigen/Geometry>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <list>

namespace meshing::internal {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using T3 = K::Triangle_3;
using Iter = std::vector<T3>::const_iterator;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, Iter>>>;
K::Point_3 pt(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d ev(const K::Point_3& p) { return {p.x(), p.y(), p.z()}; }
}  // namespace

struct TriangleTree::Impl {
  std::vector<T3> soup;
  Tree tree;
};

TriangleTree::TriangleTree(const std::vector<Eigen::Vector3d>& nodes, const std::vector<std::array<int, 3>>& tris)
    : impl_(new Impl) {
  for (const auto& t : tris) impl_->soup.emplace_back(pt(nodes[t[0]]), pt(nodes[t[1]]), pt(nodes[t[2]]));
  impl_->tree.insert(impl_->soup.begin(), impl_->soup.end());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}
TriangleTree::~TriangleTree() = default;

double TriangleTree::signed_distance(const Eigen::Vector3d& q, Eigen::Vector3d* closest, Eigen::Vector3d* normal) const {
  const auto pp = impl_->tree.closest_point_and_primitive(pt(q));
  const T3& t = *pp.second;
  const Eigen::Vector3d c = ev(pp.first);
  Eigen::Vector3d n = (ev(t[1]) - ev(t[0])).cross(ev(t[2]) - ev(t[0])).normalized();
  const double d = (q - c).norm();
  if (closest) *closest = c;
  if (normal) *normal = n;
  // Off the face interior the triangle normal can mislead; the direction to the query decides then.
  return (q - c).dot(n) < 0 ? -d : d;
}

double TriangleTree::distance(const Eigen::Vector3d& q) const {
  return std::sqrt(impl_->tree.squared_distance(pt(q)));
}

double TriangleTree::farthest_hit(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
  std::list<Tree::Intersection_and_primitive_id<K::Ray_3>::Type> hits;
  impl_->tree.all_intersections(K::Ray_3(pt(o), K::Vector_3(d.x(), d.y(), d.z())), std::back_inserter(hits));
  double best = -1;
  for (const auto& h : hits)
    if (const K::Point_3* p = boost::get<K::Point_3>(&h.first)) best = std::max(best, (ev(*p) - o).dot(d));
  return best;
}

}  // namespace meshing::internal
