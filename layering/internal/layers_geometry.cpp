// CGAL-backed queries for the layering stage (AABB tree ray casts, box-intersection of triangles).
#include "layering/internal/layers_geometry.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <mutex>

namespace layering::internal {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using P = K::Point_3;
using T3 = K::Triangle_3;
using Iter = std::vector<T3>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, Iter>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

P pt(const Eigen::Vector3d& v) { return P(v.x(), v.y(), v.z()); }
}  // namespace

std::vector<double> ray_hit_distances(const std::vector<Eigen::Vector3d>& nodes, const std::vector<Tri>& tris,
                                      const std::vector<int>& origins, const std::vector<Eigen::Vector3d>& dirs) {
  std::vector<T3> soup;
  soup.reserve(tris.size());
  for (const Tri& t : tris) soup.emplace_back(pt(nodes[t[0]]), pt(nodes[t[1]]), pt(nodes[t[2]]));
  Tree tree(soup.begin(), soup.end());
  tree.accelerate_distance_queries();
  std::vector<double> out(origins.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < origins.size(); ++i) {
    const int o = origins[i];
    const Eigen::Vector3d& d = dirs[i];
    K::Ray_3 ray(pt(nodes[o]), K::Vector_3(d.x(), d.y(), d.z()));
    auto skip = [&](Iter it) {
      const Tri& t = tris[std::size_t(it - soup.begin())];
      return t[0] == o || t[1] == o || t[2] == o;
    };
    auto hit = tree.first_intersection(ray, skip);
    if (!hit) continue;
    if (const P* p = boost::get<P>(&hit->first)) out[i] = std::sqrt(CGAL::squared_distance(*p, pt(nodes[o])));
    else if (const K::Segment_3* s = boost::get<K::Segment_3>(&hit->first))
      out[i] = std::sqrt(std::min(CGAL::squared_distance(s->source(), pt(nodes[o])),
                                  CGAL::squared_distance(s->target(), pt(nodes[o]))));
  }
  return out;
}

std::vector<std::pair<int, int>> intersecting_triangles(const std::vector<Eigen::Vector3d>& nodes,
                                                        const std::vector<Tri>& tris) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int>;
  std::vector<Box> boxes;
  boxes.reserve(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const Tri& t = tris[i];
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min({nodes[t[0]][k], nodes[t[1]][k], nodes[t[2]][k]});
      hi[k] = std::max({nodes[t[0]][k], nodes[t[1]][k], nodes[t[2]][k]});
    }
    boxes.emplace_back(lo, hi, int(i));
  }
  std::vector<std::pair<int, int>> out;
  auto test = [&](const Box& a, const Box& b) {
    const Tri& s = tris[a.info()];
    const Tri& t = tris[b.info()];
    int shared = 0, sa = -1, sb = -1;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (s[i] == t[j]) { ++shared; sa = i; sb = j; }
    bool hit = false;
    if (shared == 0) {
      hit = CGAL::do_intersect(T3(pt(nodes[s[0]]), pt(nodes[s[1]]), pt(nodes[s[2]])),
                               T3(pt(nodes[t[0]]), pt(nodes[t[1]]), pt(nodes[t[2]])));
    } else if (shared == 1) {
      const T3 ts(pt(nodes[s[0]]), pt(nodes[s[1]]), pt(nodes[s[2]]));
      const T3 tt(pt(nodes[t[0]]), pt(nodes[t[1]]), pt(nodes[t[2]]));
      const K::Segment_3 es(pt(nodes[s[(sa + 1) % 3]]), pt(nodes[s[(sa + 2) % 3]]));
      const K::Segment_3 et(pt(nodes[t[(sb + 1) % 3]]), pt(nodes[t[(sb + 2) % 3]]));
      hit = CGAL::do_intersect(es, tt) || CGAL::do_intersect(et, ts);
    }
    if (hit) out.emplace_back(a.info(), b.info());
  };
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), test);
  return out;
}

}  // namespace layering::internal
