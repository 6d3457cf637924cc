// Minimum-spanning-tree normal orientation with a cost for links across the surface; see
// orient_normals.h.
#include "scan2cad/internal/orient_normals.h"

#include <CGAL/Index_property_map.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>

namespace scan2cad::internal {

namespace {

using PN = std::pair<pipeline::Point, pipeline::Vector>;
using Iterator = std::vector<PN>::iterator;
using PointMap = CGAL::First_of_pair_property_map<PN>;
using NormalMap = CGAL::Second_of_pair_property_map<PN>;
// over a non-const vector: its iterators go into the Riemannian graph
using IteratorNeighborQuery = CGAL::Point_set_processing_3::internal::Neighbor_query<pipeline::Kernel, std::vector<PN>&, PointMap>;

}  // namespace

std::size_t orient_normals(std::vector<PN>& pn, unsigned k, double crossing_weight, std::vector<std::size_t>* reached) {
  if (reached) reached->clear();
  if (pn.empty()) return 0;
  const std::size_t n = pn.size();
  // 1. Source: the top point, its normal turned to +z (CGAL's choice).
  const Iterator top = CGAL::internal::mst_find_source(pn.begin(), pn.end(), PointMap(), NormalMap(), pipeline::Kernel());
  const std::size_t top_index = std::size_t(top - pn.begin());
  // 2. Links: as CGAL's create_riemannian_graph (point i to each of its k nearest j > i, in the
  //    order found), weights computed on all threads, edges inserted in order.
  std::vector<std::vector<std::pair<std::size_t, float>>> links(n);
  {
    IteratorNeighborQuery query(pn, PointMap());
#pragma omp parallel for schedule(static)
    for (long li = 0; li < long(n); ++li) {
      const std::size_t i = std::size_t(li);
      std::vector<Iterator> neighbors;
      query.get_iterators(pn[i].first, k, 0, std::back_inserter(neighbors));
      const pipeline::Vector& ni = pn[i].second;
      for (const Iterator& it : neighbors) {
        const std::size_t j = std::size_t(it - pn.begin());
        if (j <= i) continue;
        const pipeline::Vector& nj = it->second;
        double weight = 1.0 - std::abs(ni * nj);
        if (weight < 0) weight = 0;
        if (crossing_weight > 0) {
          const pipeline::Vector e = it->first - pn[i].first;
          const double len = std::sqrt(e.squared_length());
          if (len > 0) weight += crossing_weight * std::max(std::abs(ni * e), std::abs(nj * e)) / len;
        }
        links[i].emplace_back(j, float(weight));
      }
    }
  }
  using Graph = CGAL::internal::Riemannian_graph<Iterator>;
  Graph graph;
  for (std::size_t i = 0; i < n; ++i) graph[add_vertex(graph)].input_point = pn.begin() + long(i);
  add_vertex(graph);  // the virtual source, linked to the top point at no cost
  auto weight_map = get(boost::edge_weight, graph);
  for (std::size_t i = 0; i < n; ++i) {
    for (const auto& [j, w] : links[i]) weight_map[add_edge(vertex(i, graph), vertex(j, graph), graph).first] = w;
    if (i == top_index) weight_map[add_edge(vertex(i, graph), vertex(n, graph), graph).first] = 0.f;
  }
  links.clear();
  // 3. CGAL's tree and propagation.
  using IndexMap = CGAL::Index_property_map<Iterator>;
  const IndexMap index_map(pn.begin(), pn.end());
  auto tree = CGAL::internal::create_mst_graph(pn.begin(), pn.end(), PointMap(), NormalMap(), index_map, k,
                                               pipeline::Kernel(), graph);
  CGAL::internal::Propagate_normal_orientation<Iterator, NormalMap, pipeline::Kernel> orienter(n);
  boost::breadth_first_search(tree, boost::vertex(n, tree), visitor(boost::make_bfs_visitor(orienter)));
  // 4. The oriented points first, in input order; the others are dropped.
  std::vector<PN> kept;
  kept.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    if (tree[boost::vertex(i, tree)].is_oriented) {
      kept.push_back(pn[i]);
      if (reached) reached->push_back(i);
    }
  const std::size_t dropped = n - kept.size();
  pn.swap(kept);
  return dropped;
}

}  // namespace scan2cad::internal
