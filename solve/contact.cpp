// Penalty contact, node-to-surface or segment-to-surface (see contact.h).
//
// Choices, and why:
// - Contact points. Without slave facets each slave node is a point (node-to-surface). With
//   them, each facet is cut into n² equal sub-triangles whose centroids are the points
//   (segment-to-surface, a Gauss-point form of mortar contact): the penalty pressure is
//   integrated over the slave surface, and its force goes to the slave nodes with the facet's
//   shape functions N and to the master with the barycentric weights w of the projection, so the
//   master receives the consistent nodal loads of the pressure however the meshes are offset.
//   One-pass node-to-surface fails the contact patch test on non-matching meshes (slave forces
//   arrive at the master aliased, ±8 % interior, measured) because the slave nodes sample the
//   master's hat functions too coarsely; n = 3 (9 points per facet) samples them finely enough
//   for 1.4 % (n = 6 gives the same: the residue is the quad-corner effect of the test mesh).
//   Preferred to symmetric two-pass node-to-surface (not tried here): in 3D its nodal loads
//   still alias, and with full penalty on both passes it over-constrains (Puso & Laursen 2004).
// - Stiffness k = s·m*/Δt² with m* = m_s·m_M/(m_s + m_M) the reduced mass of the slave point
//   (m_s) and of the master point (m_M). Node points: m_s the node's mass, m_M = Σ w_i m_i.
//   Facet points: the masses of the point's area a, m_s = a·Σ N_k μ_k, m_M = a·Σ w_i μ_i, with
//   μ the nodal mass per angle-weighted area (see add_forces), so the penalty per area is
//   uniform on a uniform layer and k summed over a node's points is that of node-to-surface.
//   The two-body oscillator has ω = √(k/m*) = √s/Δt, so ωΔt = √s ≤ 1 < 2: stable for any mass
//   ratio. m* tends to the master mass (the paper's choice) when the slave is heavier and to the
//   slave mass against a heavy or rigid master. A node with zero mass (kinematic) is treated as
//   infinitely heavy. m_M is continuous across master edges, so k does not jump as a point slides.
//   Δt is the solver's contact step (Solver::contact_dt): the time step, except where elements
//   held by `fixed` are left out of the time step. The stiffness keeps the step of every
//   element then, and the solver limits the longer time step to ω·dt ≤ √(1 + ξ²) − ξ.
// - Gap: distance to the closest point of the master surface. Interior edges and vertices
//   (where the closest point of a penetrating node in a valley lies) push along (c − p)/|c − p|,
//   the gradient of the distance, so facets leave no gap; the inside/outside sign comes from the
//   angle-weighted pseudo-normal (Bærentzen & Aanæs 2005), correct at faces, edges and vertices.
//   A node beyond a boundary edge (e.g. a symmetry plane) is in contact if it is less than 10 %
//   of an edge length beyond it, pushed along the boundary facet's pseudo-normal.
// - Damping 2·ξ·m*·ω·v_n; the total normal force is clipped at zero (no adhesion).
// - Friction: elastic-slip Coulomb (a tangential spring of stiffness k with a slip limit μ·F_n,
//   history per point, saved in the restart state), so quasi-static sticking holds without creep.
// - Search: uniform grid of master triangle boxes inflated by depth + margin, O(n); re-built
//   only when a master node has moved more than the margin since the last build (the points are
//   queried at their current positions, so their motion needs no re-build).
// - Pressure: Σ_j w_ij F_j over the master tributary area A_i (1/3 of the adjacent facets). With
//   slave facets it is Σ_j w_ij F_j / Σ_j w_ij a_j over the points within the search depth: force
//   and area are gathered with the same weights, so a uniform pressure reads exactly, corners of
//   the contact zone included, and the contact edge tapers as with the plain rule.
// - Threads: each point's contact is computed independently (OpenMP, above kMinParallel items,
//   as the element loops), then gathered onto the nodes serially in point order: results do not
//   depend on the thread count, bit for bit.
#include "solve/contact.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "pipeline/error.h"
#include "solve/internal/elements.h"  // kMinParallel

namespace solve {

namespace {
using Vec = std::array<double, 3>;
inline Vec sub(const double* a, const double* b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec& a) { return std::sqrt(dot(a, a)); }
inline Vec scaled(const Vec& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline Vec unit(const Vec& a) {
  const double l = norm(a);
  return l > 0 ? scaled(a, 1 / l) : Vec{0, 0, 0};
}

}  // namespace

ContactPair::ContactPair(ContactSpec spec, std::size_t n_nodes)
    : spec_(std::move(spec)), n_nodes_(n_nodes), pressure_(n_nodes, 0.0), shear_(n_nodes, 0.0) {
  const std::string what = "contact pair '" + spec_.name + "'";
  if (spec_.master_tris.empty()) throw pipeline::bad_input(what, "no master triangles");
  if (!(spec_.penalty_scale > 0 && spec_.penalty_scale <= 1))
    throw pipeline::bad_input(what, "penalty scale " + pipeline::format_number(spec_.penalty_scale) +
                                        ", expected in (0, 1]");
  if (!(spec_.damping_ratio >= 0 && spec_.damping_ratio <= 1))
    throw pipeline::bad_input(what, "damping ratio " + pipeline::format_number(spec_.damping_ratio) +
                                        ", expected in [0, 1]");
  if (!(spec_.friction >= 0))
    throw pipeline::bad_input(what, "friction " + pipeline::format_number(spec_.friction) + ", expected >= 0");
  for (int s : spec_.slave_nodes)
    if (s < 0 || std::size_t(s) >= n_nodes)
      throw pipeline::bad_input(what, "slave node " + std::to_string(s) + " out of range [0, " +
                                          std::to_string(n_nodes) + ")");
  // Master nodes in local numbering, triangles, edges and node→triangle adjacency.
  std::map<int, int> local;
  for (std::size_t t = 0; t < spec_.master_tris.size(); ++t) {
    const auto& tri = spec_.master_tris[t];
    for (int id : tri)
      if (id < 0 || std::size_t(id) >= n_nodes)
        throw pipeline::bad_input(what, "master triangle " + std::to_string(t) + ": node " +
                                            std::to_string(id) + " out of range");
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
      throw pipeline::bad_input(what, "master triangle " + std::to_string(t) + " repeats a node");
    for (int id : tri) local.emplace(id, 0);
  }
  master_nodes_.reserve(local.size());
  for (auto& [id, l] : local) {
    l = int(master_nodes_.size());
    master_nodes_.push_back(id);
  }
  std::map<std::pair<int, int>, int> edge_id;
  node_tri_start_.assign(master_nodes_.size() + 1, 0);
  for (const auto& tri : spec_.master_tris) {
    std::array<int, 3> l{local[tri[0]], local[tri[1]], local[tri[2]]};
    tri_local_.push_back(l);
    std::array<int, 3> edges;
    for (int k = 0; k < 3; ++k) {
      const int a = l[k], b = l[(k + 1) % 3];
      auto [it, added] = edge_id.emplace(std::make_pair(std::min(a, b), std::max(a, b)),
                                         int(edge_tris_.size()));
      if (added) edge_tris_.push_back({int(tri_local_.size()) - 1, -1});
      else if (edge_tris_[std::size_t(it->second)][1] < 0)
        edge_tris_[std::size_t(it->second)][1] = int(tri_local_.size()) - 1;
      // A non-manifold edge (3+ facets) keeps its first two; the pseudo-normal degrades there.
      edges[std::size_t(k)] = it->second;
      ++node_tri_start_[std::size_t(a) + 1];
    }
    tri_edges_.push_back(edges);
  }
  for (std::size_t i = 0; i < master_nodes_.size(); ++i) node_tri_start_[i + 1] += node_tri_start_[i];
  node_tris_.resize(std::size_t(node_tri_start_.back()));
  std::vector<int> fill(node_tri_start_.begin(), node_tri_start_.end() - 1);
  for (std::size_t t = 0; t < tri_local_.size(); ++t)
    for (int l : tri_local_[t]) node_tris_[std::size_t(fill[std::size_t(l)]++)] = int(t);
  node_on_boundary_.assign(master_nodes_.size(), 0);
  for (std::size_t t = 0; t < tri_local_.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (edge_tris_[std::size_t(tri_edges_[t][std::size_t(k)])][1] < 0) {
        node_on_boundary_[std::size_t(tri_local_[t][std::size_t(k)])] = 1;
        node_on_boundary_[std::size_t(tri_local_[t][std::size_t((k + 1) % 3)])] = 1;
      }
  if (!spec_.slave_tris.empty()) {  // slave facets in slave-local indices
    if (spec_.segment_subdivision < 1 || spec_.segment_subdivision > 16)
      throw pipeline::bad_input(what, "segment subdivision " + std::to_string(spec_.segment_subdivision) +
                                          ", expected in [1, 16]");
    std::map<int, int> slave_index;
    for (std::size_t j = 0; j < spec_.slave_nodes.size(); ++j) slave_index.emplace(spec_.slave_nodes[j], int(j));
    for (const auto& tri : spec_.slave_tris) {
      std::array<int, 3> l{-1, -1, -1};
      for (int k = 0; k < 3; ++k) {
        auto it = slave_index.find(tri[std::size_t(k)]);
        if (it == slave_index.end())
          throw pipeline::bad_input(what, "slave facet node " + std::to_string(tri[std::size_t(k)]) +
                                              " is not a slave node");
        l[std::size_t(k)] = it->second;
      }
      if (l[0] == l[1] || l[1] == l[2] || l[0] == l[2])
        throw pipeline::bad_input(what, "slave facet repeats a node");
      slave_tri_local_.push_back(l);
    }
  }
  // Contact points. Facets: the centroids of the n² sub-triangles of a uniform subdivision in
  // barycentric coordinates (n(n+1)/2 upright, n(n−1)/2 inverted, equal areas), each 1/n² of the
  // facet. Nodes on no facet (all of them without facets): one point each.
  const int n_sub = spec_.segment_subdivision;
  std::vector<char> on_facet(spec_.slave_nodes.size(), 0);
  for (std::size_t t = 0; t < slave_tri_local_.size(); ++t) {
    const auto& l = slave_tri_local_[t];
    for (int k : l) on_facet[std::size_t(k)] = 1;
    auto add = [&](double b1, double b2) {
      Point pt;
      pt.node = l;
      pt.N = {1 - b1 - b2, b1, b2};
      pt.facet = int(t);
      pt.area_fraction = 1.0 / (n_sub * n_sub);
      points_.push_back(pt);
    };
    for (int i = 0; i < n_sub; ++i)
      for (int j = 0; i + j < n_sub; ++j) {
        add((i + 1.0 / 3) / n_sub, (j + 1.0 / 3) / n_sub);
        if (i + j + 1 < n_sub) add((i + 2.0 / 3) / n_sub, (j + 2.0 / 3) / n_sub);
      }
  }
  for (std::size_t j = 0; j < spec_.slave_nodes.size(); ++j)
    if (!on_facet[j]) {
      Point pt;
      pt.node = {int(j), -1, -1};
      pt.N = {1, 0, 0};
      points_.push_back(pt);
    }
  side_.assign(points_.size(), 0);
  stick_force_.assign(points_.size(), Vec{0, 0, 0});
}

std::vector<double> ContactPair::history() const {
  if (edge_length_ == 0) return {};
  // Layout: edge length, depth, margin; master positions at the last grid build (3 per master
  // node); per point: side, friction force (3).
  std::vector<double> h{edge_length_, depth_, margin_};
  h.reserve(3 + x_built_.size() + 4 * points_.size());
  h.insert(h.end(), x_built_.begin(), x_built_.end());
  for (std::size_t p = 0; p < points_.size(); ++p)
    h.insert(h.end(), {double(side_[p]), stick_force_[p][0], stick_force_[p][1], stick_force_[p][2]});
  return h;
}

void ContactPair::set_history(const std::vector<double>& h) {
  if (h.empty()) return;  // saved before the first step: nothing to restore
  const std::size_t n_built = 3 * master_nodes_.size(), expected = 3 + n_built + 4 * points_.size();
  if (!history_fits(h))
    throw pipeline::bad_input("contact pair '" + spec_.name + "'",
                              "restart history has " + std::to_string(h.size()) + " values, expected " +
                                  std::to_string(expected));
  edge_length_ = h[0];
  depth_ = h[1];
  margin_ = h[2];
  x_built_.assign(h.begin() + 3, h.begin() + 3 + long(n_built));
  grid_stale_ = true;  // re-built from x_built_ at the next call: the same grid as before the save
  const double* q = h.data() + 3 + n_built;
  for (std::size_t p = 0; p < points_.size(); ++p, q += 4) {
    side_[p] = static_cast<signed char>(q[0]);
    stick_force_[p] = {q[1], q[2], q[3]};
  }
}

void ContactPair::add_forces(const double* x, const double* v, const double* mass, double dt,
                             double dt_stiffness, double* f) {
  const std::size_t nt = tri_local_.size(), nm = master_nodes_.size(), ns = spec_.slave_nodes.size();
  auto X = [&](int local_node) { return x + 3 * std::size_t(master_nodes_[std::size_t(local_node)]); };
  // 1. Facet normals and areas, pseudo-normals and tributary areas in the current configuration.
  std::vector<Vec> face_n(nt);
  std::vector<double> area(nt);
  std::vector<std::array<double, 3>> angle(nt);
#pragma omp parallel for schedule(static) if (long(nt) > internal::kMinParallel)
  for (long t = 0; t < long(nt); ++t) {
    const auto& l = tri_local_[std::size_t(t)];
    const Vec e1 = sub(X(l[1]), X(l[0])), e2 = sub(X(l[2]), X(l[0]));
    const Vec c = cross(e1, e2);
    area[std::size_t(t)] = 0.5 * norm(c);
    face_n[std::size_t(t)] = unit(c);
    for (int k = 0; k < 3; ++k) {
      const Vec u = unit(sub(X(l[(k + 1) % 3]), X(l[k]))), w = unit(sub(X(l[(k + 2) % 3]), X(l[k])));
      angle[std::size_t(t)][std::size_t(k)] = std::acos(std::clamp(dot(u, w), -1.0, 1.0));
    }
  }
  std::vector<Vec> node_n(nm);
  std::vector<double> trib(nm), mass_area(nm);
#pragma omp parallel for schedule(static) if (long(nm) > internal::kMinParallel)
  for (long i = 0; i < long(nm); ++i) {
    Vec s{0, 0, 0};
    double a = 0, a_angle = 0;
    for (int j = node_tri_start_[std::size_t(i)]; j < node_tri_start_[std::size_t(i) + 1]; ++j) {
      const int t = node_tris_[std::size_t(j)];
      const auto& l = tri_local_[std::size_t(t)];
      const int k = l[0] == i ? 0 : (l[1] == i ? 1 : 2);
      for (int d = 0; d < 3; ++d) s[std::size_t(d)] += angle[std::size_t(t)][std::size_t(k)] * face_n[std::size_t(t)][std::size_t(d)];
      a += area[std::size_t(t)] / 3;
      a_angle += area[std::size_t(t)] * angle[std::size_t(t)][std::size_t(k)] / M_PI;
    }
    node_n[std::size_t(i)] = unit(s);
    trib[std::size_t(i)] = a;
    mass_area[std::size_t(i)] = a_angle;
  }
  if (edge_length_ == 0) {  // first call: sizes of the search from the master mesh
    double sum = 0;
    for (std::size_t t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k)
        sum += norm(sub(X(tri_local_[t][std::size_t(k)]), X(tri_local_[t][std::size_t((k + 1) % 3)])));
    edge_length_ = sum / double(3 * nt);
    depth_ = edge_length_;
    margin_ = 0.25 * edge_length_;
  }
  // Slave tributary areas (1/3 of the adjacent facets) and the contact points' positions.
  const std::size_t np = points_.size();
  std::vector<double> facet_area(slave_tri_local_.size()), slave_mass_area(ns, 0.0);
  for (std::size_t t = 0; t < slave_tri_local_.size(); ++t) {
    const auto& tri = spec_.slave_tris[t];
    const double* a = x + 3 * std::size_t(tri[0]);
    facet_area[t] = 0.5 * norm(cross(sub(x + 3 * std::size_t(tri[1]), a), sub(x + 3 * std::size_t(tri[2]), a)));
    for (int k = 0; k < 3; ++k) {
      const double* c = x + 3 * std::size_t(tri[std::size_t(k)]);
      const Vec u = unit(sub(x + 3 * std::size_t(tri[std::size_t((k + 1) % 3)]), c));
      const Vec w = unit(sub(x + 3 * std::size_t(tri[std::size_t((k + 2) % 3)]), c));
      slave_mass_area[std::size_t(slave_tri_local_[t][std::size_t(k)])] +=
          facet_area[t] * std::acos(std::clamp(dot(u, w), -1.0, 1.0)) / M_PI;
    }
  }
  auto point_x = [&](std::size_t pi) {
    const Point& pt = points_[pi];
    Vec q{0, 0, 0};
    for (int k = 0; k < 3; ++k)
      if (pt.node[std::size_t(k)] >= 0) {
        const double* xs = x + 3 * std::size_t(spec_.slave_nodes[std::size_t(pt.node[std::size_t(k)])]);
        for (int d = 0; d < 3; ++d) q[std::size_t(d)] += pt.N[std::size_t(k)] * xs[d];
      }
    return q;
  };
  // 2. Re-build the search grid when a master node has moved more than the margin (after a
  // restart: re-build it from the saved positions of its last build, so it is the same grid).
  bool rebuild = x_built_.size() != 3 * nm;
  for (std::size_t i = 0; i < nm && !rebuild; ++i) {
    const Vec d = sub(X(int(i)), &x_built_[3 * i]);
    rebuild = dot(d, d) > margin_ * margin_;
  }
  if (rebuild || grid_stale_) {
    if (rebuild) {
      x_built_.resize(3 * nm);
      for (std::size_t i = 0; i < nm; ++i)
        for (int d = 0; d < 3; ++d) x_built_[3 * i + std::size_t(d)] = X(int(i))[d];
    }
    grid_stale_ = false;
    auto XB = [&](int local_node) { return &x_built_[3 * std::size_t(local_node)]; };
    auto& boxes = boxes_;
    boxes.resize(nt);
    const double inflate = depth_ + margin_;
    for (std::size_t t = 0; t < nt; ++t) {
      auto& b = boxes[t];
      for (int d = 0; d < 3; ++d) {
        double lo = XB(tri_local_[t][0])[d], hi = lo;
        for (int k = 1; k < 3; ++k) {
          lo = std::min(lo, XB(tri_local_[t][std::size_t(k)])[d]);
          hi = std::max(hi, XB(tri_local_[t][std::size_t(k)])[d]);
        }
        b[std::size_t(d)] = lo - inflate;
        b[std::size_t(d) + 3] = hi + inflate;
      }
    }
    grid_.build(boxes, 0.5);  // half-box cells: ~4× fewer candidates per query on a surface
    // Visit the points cell by cell (cache locality only: each point's result is stored at its
    // own index, so the order changes nothing in the results).
    std::vector<std::pair<long, int>> key(np);
    for (std::size_t j = 0; j < np; ++j) key[j] = {grid_.cell_of(point_x(j).data()), int(j)};
    std::sort(key.begin(), key.end());
    slave_order_.resize(np);
    for (std::size_t j = 0; j < np; ++j) slave_order_[j] = key[j].second;
  }
  // 3. Per contact point: closest master point, gap, penalty, damping and friction forces.
  auto& contact = point_contact_;
  auto& point_area = point_area_;
  contact.resize(np);
  point_area.resize(np);
  const double s_pen = spec_.penalty_scale, xi = spec_.damping_ratio, mu = spec_.friction;
  const double omega = std::sqrt(s_pen) / dt_stiffness, boundary_tol = 0.1 * edge_length_;
  const bool two_sided = spec_.two_sided;
#pragma omp parallel for schedule(dynamic, 256) if (long(np) > internal::kMinParallel)
  for (long js = 0; js < long(np); ++js) {
    const std::size_t j = std::size_t(slave_order_[std::size_t(js)]);
    contact[j] = PointContact{};
    point_area[j] = 0;
    const Point& pt = points_[j];
    const Vec px = point_x(j);
    const double* p = px.data();
    const long cell = grid_.cell_of(p);
    internal::ClosestPoint best{};
    int best_tri = -1;
    if (cell >= 0)
      for (const int* it = grid_.begin(cell); it != grid_.end(cell); ++it) {
        const auto& b = boxes_[std::size_t(*it)];
        if (p[0] < b[0] || p[0] > b[3] || p[1] < b[1] || p[1] > b[4] || p[2] < b[2] || p[2] > b[5]) continue;
        const auto& l = tri_local_[std::size_t(*it)];
        // The plane distance bounds the distance to the triangle from below: skip early.
        const double plane = dot(sub(p, X(l[0])), face_n[std::size_t(*it)]);
        const double bound = best_tri < 0 ? depth_ * depth_ : best.dist2;
        if (plane * plane > bound) continue;
        const auto cp = internal::closest_point_on_triangle(p, X(l[0]), X(l[1]), X(l[2]));
        if (best_tri < 0 || cp.dist2 < best.dist2) {  // ties: the first in the cell (lower id)
          best = cp;
          best_tri = *it;
        }
      }
    if (best_tri < 0 || best.dist2 > depth_ * depth_) {
      side_[j] = 0;
      stick_force_[j] = {0, 0, 0};
      continue;
    }
    contact[j].tri = best_tri;  // over the master: its area counts for the pressure
    contact[j].w = best.weight;
    // Pseudo-normal of the feature, and whether the feature lies on the master's boundary.
    const std::size_t t = std::size_t(best_tri);
    const auto& l = tri_local_[t];
    Vec n_ps = face_n[t];
    bool boundary = false;
    const int feature = int(best.feature);
    if (feature >= 1 && feature <= 3) {
      const auto& et = edge_tris_[std::size_t(tri_edges_[t][std::size_t(feature - 1)])];
      if (et[1] < 0) boundary = true;
      else {
        const Vec& a = face_n[std::size_t(et[0])];
        const Vec& b = face_n[std::size_t(et[1])];
        n_ps = unit(Vec{a[0] + b[0], a[1] + b[1], a[2] + b[2]});
      }
    } else if (feature >= 4) {
      const int node = l[std::size_t(feature - 4)];
      n_ps = node_n[std::size_t(node)];
      boundary = node_on_boundary_[std::size_t(node)] != 0;
    }
    const Vec diff = sub(p, best.point.data());
    const double g = dot(diff, n_ps), d = std::sqrt(best.dist2);
    if (two_sided && side_[j] == 0) side_[j] = g >= 0 ? 1 : -1;
    const double side = two_sided ? side_[j] : 1;
    // The point's masses: a facet point carries area a = area_fraction of its facet and the
    // mass a·μ of each side, μ the nodal mass per area interpolated at the point (slave: by N,
    // master: by w). The nodal areas are angle-weighted (each corner angle/π of a facet): on a
    // quadrilateral face split into two triangles they are the quarter cells the lumped masses
    // of hexahedra and wedges stand for, so μ is uniform on a uniform layer, corners included
    // (the 1/3 rule gives the corners 1/6 or 1/3 of a cell: ±50 % penalty there). A node point
    // (no area) takes whole nodal masses.
    double m_slave = 0, m_master = 0;
    if (pt.facet >= 0) {
      const double a = pt.area_fraction * facet_area[std::size_t(pt.facet)];
      point_area[j] = a;
      for (int k = 0; k < 3; ++k) {
        const std::size_t sl = std::size_t(pt.node[std::size_t(k)]);
        if (slave_mass_area[sl] > 0)
          m_slave += pt.N[std::size_t(k)] * a * mass[spec_.slave_nodes[sl]] / slave_mass_area[sl];
      }
      for (int k = 0; k < 3; ++k) {
        const std::size_t ml = std::size_t(l[std::size_t(k)]);
        if (mass_area[ml] > 0) m_master += best.weight[std::size_t(k)] * a * mass[master_nodes_[ml]] / mass_area[ml];
      }
    } else {
      m_slave = mass[spec_.slave_nodes[std::size_t(pt.node[0])]];
      for (int k = 0; k < 3; ++k) m_master += best.weight[std::size_t(k)] * mass[master_nodes_[std::size_t(l[std::size_t(k)])]];
    }
    if (side * g >= 0) {  // outside: no contact
      stick_force_[j] = {0, 0, 0};
      continue;
    }
    Vec n;  // outward contact normal (slave is pushed along it)
    double pen;
    if (boundary) {
      const Vec lateral{diff[0] - g * n_ps[0], diff[1] - g * n_ps[1], diff[2] - g * n_ps[2]};
      if (norm(lateral) > boundary_tol) {  // beyond the master's edge
        stick_force_[j] = {0, 0, 0};
        contact[j].tri = -1;
        continue;
      }
      n = scaled(n_ps, side);
      pen = -side * g;
    } else if (d > 1e-12 * edge_length_) {
      n = scaled(diff, -1 / d);
      pen = d;
    } else {
      n = scaled(n_ps, side);
      pen = 0;
    }
    // Reduced mass, stiffness and damping.
    double m_red = m_slave > 0 && m_master > 0 ? m_slave * m_master / (m_slave + m_master)
                                               : std::max(m_slave, m_master);
    if (!(m_red > 0)) continue;
    const double k_pen = s_pen * m_red / (dt_stiffness * dt_stiffness);
    Vec v_rel{0, 0, 0};
    for (int k = 0; k < 3; ++k)
      if (pt.node[std::size_t(k)] >= 0) {
        const double* vs = v + 3 * std::size_t(spec_.slave_nodes[std::size_t(pt.node[std::size_t(k)])]);
        for (int q = 0; q < 3; ++q) v_rel[std::size_t(q)] += pt.N[std::size_t(k)] * vs[q];
      }
    for (int k = 0; k < 3; ++k) {
      const double* vm = v + 3 * std::size_t(master_nodes_[std::size_t(l[std::size_t(k)])]);
      for (int q = 0; q < 3; ++q) v_rel[std::size_t(q)] -= best.weight[std::size_t(k)] * vm[q];
    }
    const double vn = dot(v_rel, n);
    const double fn = std::max(0.0, k_pen * pen - 2 * xi * m_red * omega * vn);
    PointContact& c = contact[j];
    c.touching = true;
    c.fn = fn;
    c.normal_force = scaled(n, fn);
    c.penetration = pen;
    if (mu > 0) {  // elastic-slip Coulomb friction
      Vec ft = stick_force_[j];
      const double mag = norm(ft);
      const double fn_dot = dot(ft, n);
      ft = {ft[0] - fn_dot * n[0], ft[1] - fn_dot * n[1], ft[2] - fn_dot * n[2]};
      ft = scaled(unit(ft), mag);  // rotate the history into the current tangent plane
      for (int q = 0; q < 3; ++q) ft[std::size_t(q)] -= k_pen * dt * (v_rel[std::size_t(q)] - vn * n[std::size_t(q)]);
      const double limit = mu * fn, now = norm(ft);
      if (now > limit) ft = scaled(ft, limit / now);
      stick_force_[j] = ft;
      c.tangent_force = ft;
    }
  }
  // 4. Deterministic gather in point order: nodal forces, master pressure and shear.
  const bool segments = !slave_tri_local_.empty();
  std::vector<double> normal_sum(nm, 0.0), area_sum(nm, 0.0);
  std::vector<Vec> shear_sum(nm, Vec{0, 0, 0});
  resultant_ = {0, 0, 0};
  max_penetration_ = 0;
  for (std::size_t j = 0; j < np; ++j) {
    const PointContact& c = contact[j];
    if (c.tri < 0) continue;
    const auto& l = tri_local_[std::size_t(c.tri)];
    if (segments)
      for (int k = 0; k < 3; ++k) area_sum[std::size_t(l[std::size_t(k)])] += c.w[std::size_t(k)] * point_area[j];
    if (!c.touching) continue;
    Vec force;
    for (int q = 0; q < 3; ++q) force[std::size_t(q)] = c.normal_force[std::size_t(q)] + c.tangent_force[std::size_t(q)];
    const Point& pt = points_[j];
    for (int k = 0; k < 3; ++k)
      if (pt.node[std::size_t(k)] >= 0) {
        const std::size_t s = std::size_t(spec_.slave_nodes[std::size_t(pt.node[std::size_t(k)])]);
        for (int q = 0; q < 3; ++q) f[3 * s + std::size_t(q)] += pt.N[std::size_t(k)] * force[std::size_t(q)];
      }
    for (int q = 0; q < 3; ++q) resultant_[std::size_t(q)] += force[std::size_t(q)];
    for (int k = 0; k < 3; ++k) {
      const std::size_t m = std::size_t(l[std::size_t(k)]);
      const double w = c.w[std::size_t(k)];
      const std::size_t node = std::size_t(master_nodes_[m]);
      for (int q = 0; q < 3; ++q) {
        f[3 * node + std::size_t(q)] -= w * force[std::size_t(q)];
        shear_sum[m][std::size_t(q)] += w * c.tangent_force[std::size_t(q)];
      }
      normal_sum[m] += w * c.fn;
    }
    if (c.penetration > max_penetration_) {
      max_penetration_ = c.penetration;
      deepest_point_ = point_x(j);
    }
  }
  for (std::size_t i = 0; i < nm; ++i) {
    const std::size_t node = std::size_t(master_nodes_[i]);
    const double area = segments ? area_sum[i] : trib[i];
    pressure_[node] = area > 0 ? normal_sum[i] / area : 0;
    shear_[node] = area > 0 ? norm(shear_sum[i]) / area : 0;
  }
}

}  // namespace solve
