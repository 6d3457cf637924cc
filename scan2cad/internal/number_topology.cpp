#include "scan2cad/internal/number_topology.h"

#include <gmsh.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace scan2cad::internal {

namespace {

constexpr int line_type = 1, triangle_type = 2;  // gmsh element types

struct Entity {
  int dim = 0, tag = 0;
  std::vector<int> boundary;  // a curve's (begin, end) points; a surface's signed curves
  std::vector<std::size_t> nodes;
  std::vector<double> xyz;
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> elements, element_nodes;
};

void sort_nodes(Entity& e) {
  std::vector<std::size_t> order(e.nodes.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return e.nodes[a] < e.nodes[b]; });
  std::vector<std::size_t> nodes;
  std::vector<double> xyz;
  for (std::size_t i : order) {
    nodes.push_back(e.nodes[i]);
    xyz.insert(xyz.end(), e.xyz.begin() + 3 * long(i), e.xyz.begin() + 3 * long(i) + 3);
  }
  e.nodes = std::move(nodes), e.xyz = std::move(xyz);
}

Entity read_entity(int dim, int tag) {
  Entity e;
  e.dim = dim, e.tag = tag;
  std::vector<double> parametric;
  gmsh::model::mesh::getNodes(e.nodes, e.xyz, parametric, dim, tag, false, false);
  sort_nodes(e);
  gmsh::model::mesh::getElements(e.types, e.elements, e.element_nodes, dim, tag);
  if (dim == 1) {  // (begin, end); getBoundary gives a curve's two points one sign, not their order
    std::vector<int> up;
    gmsh::model::getAdjacencies(dim, tag, up, e.boundary);
  } else if (dim == 2) {
    gmsh::vectorpair boundary;
    gmsh::model::getBoundary({{dim, tag}}, boundary, false, true, false);
    for (const auto& b : boundary) e.boundary.push_back(b.second);
  }
  return e;
}

// Every node tag on the entity, its own and its elements', in increasing order: entities are
// numbered by these, compared as words (curves meeting at a corner share their smallest node).
std::vector<std::size_t> node_key(const Entity& e) {
  std::vector<std::size_t> key = e.nodes;
  for (const auto& nodes : e.element_nodes) key.insert(key.end(), nodes.begin(), nodes.end());
  std::sort(key.begin(), key.end());
  key.erase(std::unique(key.begin(), key.end()), key.end());
  return key;
}

std::size_t smallest_line_node(const Entity& curve) {
  std::size_t smallest = SIZE_MAX;
  for (std::size_t t = 0; t < curve.types.size(); ++t)
    if (curve.types[t] == line_type)
      for (std::size_t n : curve.element_nodes[t]) smallest = std::min(smallest, n);
  return smallest;
}

// createTopology puts the one point of a closed curve (a respirator's rim, a loop between two
// parts) on a node of its choosing, also by address: the point moves to the curve's smallest
// node, where its lines will start, and the node it held joins the curve's own. A point another
// curve also ends at stays where it is.
void move_closed_curve_points(std::vector<Entity>& entities) {
  std::map<std::pair<int, int>, std::size_t> at;  // (dim, tag) → index
  std::map<int, int> curves_ending_at;            // point tag → curves that end there
  for (std::size_t i = 0; i < entities.size(); ++i) {
    at[{entities[i].dim, entities[i].tag}] = i;
    if (entities[i].dim == 1)
      for (int p : std::set<int>(entities[i].boundary.begin(), entities[i].boundary.end())) ++curves_ending_at[p];
  }
  for (Entity& curve : entities) {
    if (curve.dim != 1 || curve.boundary.size() != 2 || curve.boundary[0] != curve.boundary[1]) continue;
    const auto p = at.find({0, curve.boundary[0]});
    if (p == at.end() || curves_ending_at[curve.boundary[0]] != 1) continue;
    Entity& point = entities[p->second];
    const std::size_t smallest = smallest_line_node(curve);
    const auto own = std::find(curve.nodes.begin(), curve.nodes.end(), smallest);
    if (point.nodes.size() != 1 || own == curve.nodes.end()) continue;
    const std::size_t i = std::size_t(own - curve.nodes.begin());
    std::swap(point.nodes[0], curve.nodes[i]);
    for (int k = 0; k < 3; ++k) std::swap(point.xyz[std::size_t(k)], curve.xyz[3 * i + std::size_t(k)]);
    for (auto& nodes : point.element_nodes)
      for (std::size_t& n : nodes) n = point.nodes[0];
    sort_nodes(curve);
  }
}

using Neighbours = std::map<std::size_t, std::vector<std::size_t>>;

Neighbours neighbours_along(const std::vector<std::size_t>& lines) {
  Neighbours n;
  for (std::size_t k = 0; k + 1 < lines.size(); k += 2) {
    n[lines[k]].push_back(lines[k + 1]);
    n[lines[k + 1]].push_back(lines[k]);
  }
  return n;
}

// The `count` node pairs of a curve's lines walked from `start` through `next`; empty if the
// lines are not one chain through those two.
std::vector<std::size_t> walk(Neighbours& neighbours, std::size_t count, std::size_t start, std::size_t next) {
  std::vector<std::size_t> walked = {start, next};
  for (std::size_t previous = start, at = next; walked.size() < count && at != start;) {
    const auto& n = neighbours[at];
    const auto onward = std::find_if(n.begin(), n.end(), [&](std::size_t v) { return v != previous; });
    if (onward == n.end()) break;
    walked.insert(walked.end(), {at, *onward});
    previous = at, at = *onward;
  }
  if (walked.size() != count) return {};
  return walked;
}

// Directs the curve as number_topology_by_node_tags says and returns its first line
// ((0, 0) if it has none or they are not one chain, which leaves it as it was).
std::pair<std::size_t, std::size_t> direct_curve(Entity& curve, const std::map<int, std::size_t>& point_node) {
  for (std::size_t t = 0; t < curve.types.size(); ++t) {
    if (curve.types[t] != line_type || curve.element_nodes[t].empty()) continue;
    std::vector<std::size_t>& lines = curve.element_nodes[t];
    Neighbours neighbours = neighbours_along(lines);
    std::size_t start = smallest_line_node(curve);  // closed: its point is there (move_closed_curve_points)
    bool swap_ends = false;
    if (curve.boundary.size() == 2 && curve.boundary[0] != curve.boundary[1]) {
      const std::size_t begin = point_node.at(curve.boundary[0]), end = point_node.at(curve.boundary[1]);
      swap_ends = begin > end;
      start = std::min(begin, end);
    }
    const auto& first = neighbours[start];
    if (first.empty()) return {0, 0};
    const std::vector<std::size_t> walked =
        walk(neighbours, lines.size(), start, *std::min_element(first.begin(), first.end()));
    if (walked.empty()) return {0, 0};
    if (swap_ends) std::swap(curve.boundary[0], curve.boundary[1]);
    lines = walked;
    std::sort(curve.elements[t].begin(), curve.elements[t].end());
    return {walked[0], walked[1]};
  }
  return {0, 0};
}

}  // namespace

void number_topology_by_node_tags() {
  gmsh::vectorpair dim_tags;
  gmsh::model::getEntities(dim_tags);
  std::vector<Entity> entities;
  for (const auto& [dim, tag] : dim_tags) entities.push_back(read_entity(dim, tag));
  move_closed_curve_points(entities);

  std::map<std::pair<int, int>, int> new_tag;  // (dim, old tag) → tag; surfaces keep theirs
  for (int dim : {0, 1}) {
    std::vector<std::pair<std::vector<std::size_t>, int>> by_node;
    for (const Entity& e : entities)
      if (e.dim == dim) by_node.push_back({node_key(e), e.tag});
    std::sort(by_node.begin(), by_node.end());
    for (std::size_t i = 0; i < by_node.size(); ++i) new_tag[{dim, by_node[i].second}] = int(i) + 1;
  }
  for (Entity& e : entities) {
    if (e.dim < 2) e.tag = new_tag.at({e.dim, e.tag});
    for (int& b : e.boundary) b = (b < 0 ? -1 : 1) * new_tag.at({e.dim - 1, std::abs(b)});
  }

  std::map<int, std::size_t> point_node;  // point tag → its node's tag
  for (const Entity& e : entities)
    if (e.dim == 0 && !e.nodes.empty()) point_node[e.tag] = e.nodes.front();
  std::map<int, std::pair<std::size_t, std::size_t>> first_line;  // curve tag → its first line
  for (Entity& e : entities)
    if (e.dim == 1) first_line[e.tag] = direct_curve(e, point_node);

  for (Entity& e : entities) {
    if (e.dim != 2) continue;
    std::set<std::pair<std::size_t, std::size_t>> half_edges;
    for (std::size_t t = 0; t < e.types.size(); ++t)
      if (e.types[t] == triangle_type)
        for (std::size_t k = 0; k + 2 < e.element_nodes[t].size(); k += 3)
          for (std::size_t j = 0; j < 3; ++j)
            half_edges.insert({e.element_nodes[t][k + j], e.element_nodes[t][k + (j + 1) % 3]});
    for (int& b : e.boundary) {
      const auto line = first_line.find(std::abs(b));
      if (line != first_line.end() && line->second.first != 0)
        b = (half_edges.count(line->second) ? 1 : -1) * std::abs(b);
    }
    std::sort(e.boundary.begin(), e.boundary.end(), [](int a, int b) { return std::abs(a) < std::abs(b); });
  }

  std::sort(entities.begin(), entities.end(),
            [](const Entity& a, const Entity& b) { return std::make_pair(a.dim, a.tag) < std::make_pair(b.dim, b.tag); });
  std::string name;
  gmsh::model::getCurrent(name);
  gmsh::model::remove();
  gmsh::model::add(name);
  for (const Entity& e : entities) gmsh::model::addDiscreteEntity(e.dim, e.tag, e.boundary);
  for (const Entity& e : entities) {
    gmsh::model::mesh::addNodes(e.dim, e.tag, e.nodes, e.xyz);
    gmsh::model::mesh::addElements(e.dim, e.tag, e.types, e.elements, e.element_nodes);
  }
}

}  // namespace scan2cad::internal
