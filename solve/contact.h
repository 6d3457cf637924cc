#pragma once
/// Penalty contact (DESIGN.md, physics): a slave side against a master surface of triangles, as
/// node-to-surface points or, when the slave group is a surface, as points integrated over its
/// facets (segment-to-surface, ContactSpec::slave_tris); spring stiffness k = s·m*/Δt² with m* the
/// reduced mass of the slave and master points (DESIGN.md's m is the master's mass: contact.cpp
/// says why), viscous contact damping 2·ξ·m*·ω·v along the master normal (ξ = damping_ratio, 0
/// unless the deck sets it), optional Coulomb friction. The search is re-run as the bodies move and
/// scales as n log n or better. This header is the interface between the time integrator and contact.
#include <array>
#include <string>
#include <vector>

#include "solve/internal/contact_geometry.h"

namespace solve {

/// One contact pair as given in the deck. Node ids index the model's node arrays.
struct ContactSpec {
  std::string name;
  std::vector<int> slave_nodes;                ///< slave node ids (respirator inner surface, strap nodes)
  std::vector<std::array<int, 3>> master_tris; ///< master facets (head skin); outward normal by the right-hand rule
  double penalty_scale = 0.1;                  ///< s in k = s·m*/Δt², m* the slave and master masses' reduced mass (the paper: 0.1, with the master's mass), range (0, 1]
  double damping_ratio = 0.0;                  ///< ξ of the viscous contact damping 2·ξ·m*·ω·v, ω = √(k/m*); range [0, 1]
  double friction = 0.0;                       ///< Coulomb coefficient μ ≥ 0 (0: frictionless; a deck allows at most 2)
  bool two_sided = false;                      ///< thin shells: slaves are pushed out on either side
  // A master node of zero mass (a kinematic one) counts as infinitely heavy: such a master is a
  // rigid wall (contact.cpp).
  /// Slave surface facets (node ids, every corner a slave node; the Solver fills them when the
  /// slave group is a surface). When given, contact is integrated over the slave surface
  /// (segment-to-surface): each facet is cut into segment_subdivision² sub-triangles whose
  /// centroids are the contact points, each carrying its share of the facet area and of the slave
  /// mass; slave nodes on no facet stay node-to-surface points. Without facets every slave node is
  /// one point (node-to-surface). See contact.cpp for why.
  std::vector<std::array<int, 3>> slave_tris;
  int segment_subdivision = 3;                 ///< sub-triangles per facet edge, ≥ 1 (used with slave_tris)
};

/// State and outputs of one contact pair.
class ContactPair {
 public:
  /// @param spec     the pair; node ids must be < n_nodes (throws pipeline::Error(bad_input) otherwise)
  /// @param n_nodes  number of nodes of the whole model
  ContactPair(ContactSpec spec, std::size_t n_nodes);

  /// Adds the contact forces of this pair to f.
  /// @param[in]     x     current positions, n_nodes×3 row-major [mm]
  /// @param[in]     v     current velocities, n_nodes×3 [mm/ms]
  /// @param[in]     mass  lumped nodal masses, n_nodes [g]
  /// @param[in]     dt    global time step [ms]
  /// @param[in]     dt_stiffness  the step the penalty is set with, k = s·m*/dt_stiffness² [ms]:
  ///                      the step of every element, held or not (Solver::contact_dt), so that a
  ///                      stage that holds the head presses as hard as one that frees it
  /// @param[in,out] f     nodal forces, n_nodes×3 [N]; contact forces are added (slave and master sides)
  void add_forces(const double* x, const double* v, const double* mass, double dt, double dt_stiffness, double* f);
  /// The same with the penalty set by the time step itself (dt_stiffness = dt).
  void add_forces(const double* x, const double* v, const double* mass, double dt, double* f) {
    add_forces(x, v, mass, dt, dt, f);
  }

  /// Normal contact pressure per node after the last add_forces, [MPa]: normal contact force
  /// gathered on the master nodes divided by their tributary area (1/3 of the adjacent facets;
  /// with spec.slave_tris: by the slave area of the contact points gathered with the same
  /// weights, i.e. the consistent area); 0 away from contact.
  /// Size n_nodes, nonzero on master nodes only.
  const std::vector<double>& pressure() const { return pressure_; }
  /// Tangential (shear) contact traction per node, [MPa], like pressure(). Size n_nodes.
  const std::vector<double>& shear() const { return shear_; }
  /// Resultant contact force on the slave side after the last add_forces [N].
  std::array<double, 3> resultant_force() const { return resultant_; }
  /// Deepest penetration of a slave point (a node, or a facet's contact point) after the last
  /// add_forces [mm] (0 if none).
  double max_penetration() const { return max_penetration_; }
  /// Where that deepest slave point was, in the positions given to the last add_forces [mm]
  /// (a run that stops on penetration names the place).
  std::array<double, 3> deepest_point() const { return deepest_point_; }
  const ContactSpec& spec() const { return spec_; }
  /// Number of contact points (slave nodes, or facet sub-triangles with spec.slave_tris).
  std::size_t n_points() const { return points_.size(); }

  /// History needed to continue a run exactly (restart file): the search sizes fixed at the first
  /// call, and per contact point the side of a two-sided master and the elastic-slip friction
  /// force. Empty before the first add_forces.
  std::vector<double> history() const;
  /// Restores history(). @throws pipeline::Error(bad_input) if the size does not fit this pair.
  void set_history(const std::vector<double>& h);
  /// Whether h (from history()) was written by a pair of this size (empty fits).
  bool history_fits(const std::vector<double>& h) const {
    return h.empty() || h.size() == 3 + 3 * master_nodes_.size() + 4 * points_.size();
  }

 private:
  ContactSpec spec_;
  std::size_t n_nodes_;
  std::vector<double> pressure_, shear_;
  std::array<double, 3> resultant_{0, 0, 0};
  double max_penetration_ = 0;
  std::array<double, 3> deepest_point_{0, 0, 0};
  // Implementation state (contact.cpp). Master topology in local master-node indices:
  std::vector<int> master_nodes_;                ///< distinct master node ids
  std::vector<std::array<int, 3>> tri_local_;    ///< master_tris as indices into master_nodes_
  std::vector<std::array<int, 3>> tri_edges_;    ///< edge ids of each triangle (edge k: corners k, k+1)
  std::vector<std::array<int, 2>> edge_tris_;    ///< the triangles of each edge (-1: boundary edge)
  std::vector<int> node_tri_start_, node_tris_;  ///< triangles around each master node (CSR)
  std::vector<char> node_on_boundary_;           ///< master node on a boundary edge
  std::vector<std::array<int, 3>> slave_tri_local_;  ///< slave_tris as indices into slave_nodes
  /// A contact point: x = Σ N_k x(node_k) over up to 3 slave nodes (slave-local; -1 unused).
  /// facet ≥ 0: a sub-triangle centroid of that slave facet, carrying area_fraction of its area;
  /// facet < 0: a slave node alone (node-to-surface).
  struct Point {
    std::array<int, 3> node{-1, -1, -1};
    std::array<double, 3> N{0, 0, 0};
    int facet = -1;
    double area_fraction = 0;
  };
  std::vector<Point> points_;
  double edge_length_ = 0;                       ///< mean master edge length at the first call [mm]
  double depth_ = 0;                             ///< deepest penetration searched for [mm]
  double margin_ = 0;                            ///< grid reused until a master node moves this far [mm]
  std::vector<std::array<double, 6>> boxes_;     ///< master triangle boxes inflated by depth + margin
  internal::BoxGrid grid_;                       ///< bucket sort of boxes_
  std::vector<double> x_built_;                  ///< master node positions at the last grid build
  bool grid_stale_ = false;                      ///< restored history: re-build the grid from x_built_
  std::vector<int> slave_order_;                 ///< contact points sorted by grid cell (memory locality)
  // Per-point history: side of a two-sided master (+1/-1, 0 unknown), elastic-slip friction force [N].
  std::vector<signed char> side_;
  std::vector<std::array<double, 3>> stick_force_;
  /// One contact point's result in a step, computed in parallel and gathered serially.
  struct PointContact {
    int tri = -1;          ///< master triangle of the closest point within the search depth, -1: none
    bool touching = false; ///< penetrating: forces are applied
    std::array<double, 3> w{0, 0, 0};  ///< barycentric weights of the contact point
    std::array<double, 3> normal_force{0, 0, 0}, tangent_force{0, 0, 0};  ///< on the slave [N]
    double fn = 0;         ///< normal force magnitude [N]
    double penetration = 0;
  };
  // Kept from step to step and reset point by point inside the parallel loop. Allocated and
  // zero-filled afresh every step (~35 MB at 363k points) on one thread, they made two-thread
  // segment-to-surface steps 5-15 % longer (bench_contact, paired runs 2026-12-06: 220-230 ->
  // 196-197 ms, and 163-178 -> 156-158 ms on a faster hour); one thread: the same within the noise.
  std::vector<PointContact> point_contact_;
  std::vector<double> point_area_;  ///< [mm²] the area a facet point stands for, 0 for none
};

}  // namespace solve
