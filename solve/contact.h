#pragma once
/// Penalty node-to-surface contact (DESIGN.md, physics): slave nodes against a master surface of
/// triangles, spring stiffness k = s·m/Δt² and viscous contact damping 2·m·ω·v along the master
/// normal, optional Coulomb friction. The search is re-run as the bodies move and scales as
/// n log n or better. This header is the interface between the time integrator and contact.
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
  double penalty_scale = 0.1;                  ///< s in k = s·m/Δt² (the paper: 0.1), range (0, 1]
  double damping_ratio = 0.0;                  ///< ξ of the viscous contact damping 2·m·ω·v, ω = √(k/m); range [0, 1]
  double friction = 0.0;                       ///< Coulomb coefficient μ ≥ 0 (0: frictionless)
  bool two_sided = false;                      ///< thin shells: slaves are pushed out on either side
  /// Optional slave surface facets (node ids; corners outside slave_nodes are ignored). When
  /// given, pressure() divides the gathered normal force by the slave area gathered with the
  /// same weights instead of the master tributary area: exact for a uniform pressure on
  /// non-matching meshes (no aliasing when the slave spacing is not a multiple of the master's).
  std::vector<std::array<int, 3>> slave_tris;
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
  /// @param[in,out] f     nodal forces, n_nodes×3 [N]; contact forces are added (slave and master sides)
  void add_forces(const double* x, const double* v, const double* mass, double dt, double* f);

  /// Normal contact pressure per node after the last add_forces, [MPa]: normal contact force
  /// gathered on the master nodes divided by their tributary area (1/3 of the adjacent facets;
  /// with spec.slave_tris: by the slave area gathered the same way); 0 away from contact.
  /// Size n_nodes, nonzero on master nodes only.
  const std::vector<double>& pressure() const { return pressure_; }
  /// Tangential (shear) contact traction per node, [MPa], like pressure(). Size n_nodes.
  const std::vector<double>& shear() const { return shear_; }
  /// Resultant contact force on the slave side after the last add_forces [N].
  std::array<double, 3> resultant_force() const { return resultant_; }
  /// Deepest penetration of a slave node after the last add_forces [mm] (0 if none).
  double max_penetration() const { return max_penetration_; }
  const ContactSpec& spec() const { return spec_; }

 private:
  ContactSpec spec_;
  std::size_t n_nodes_;
  std::vector<double> pressure_, shear_;
  std::array<double, 3> resultant_{0, 0, 0};
  double max_penetration_ = 0;
  // Implementation state (contact.cpp). Master topology in local master-node indices:
  std::vector<int> master_nodes_;                ///< distinct master node ids
  std::vector<std::array<int, 3>> tri_local_;    ///< master_tris as indices into master_nodes_
  std::vector<std::array<int, 3>> tri_edges_;    ///< edge ids of each triangle (edge k: corners k, k+1)
  std::vector<std::array<int, 2>> edge_tris_;    ///< the triangles of each edge (-1: boundary edge)
  std::vector<int> node_tri_start_, node_tris_;  ///< triangles around each master node (CSR)
  std::vector<char> node_on_boundary_;           ///< master node on a boundary edge
  std::vector<std::array<int, 3>> slave_tri_local_;  ///< slave_tris as indices into slave_nodes (-1: none)
  double edge_length_ = 0;                       ///< mean master edge length at the first call [mm]
  double depth_ = 0;                             ///< deepest penetration searched for [mm]
  double margin_ = 0;                            ///< grid reused until a master node moves this far [mm]
  std::vector<std::array<double, 6>> boxes_;     ///< master triangle boxes inflated by depth + margin
  internal::BoxGrid grid_;                       ///< bucket sort of boxes_
  std::vector<double> x_built_;                  ///< master node positions at the last grid build
  std::vector<int> slave_order_;                 ///< slaves sorted by grid cell (memory locality)
  // Per-slave history: side of a two-sided master (+1/-1, 0 unknown), elastic-slip friction force [N].
  std::vector<signed char> side_;
  std::vector<std::array<double, 3>> stick_force_;
};

}  // namespace solve
