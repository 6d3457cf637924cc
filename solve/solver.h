#pragma once
/// The explicit time integrator: central differences with lumped mass (DESIGN.md, physics).
///
///   m (v_{n+½} − v_{n−½})/Δt = f_int(x_n) + f_ext(t_n) + f_contact(x_n, v_{n−½}) − α m (v_{n+½}+v_{n−½})/2
///   x_{n+1} = x_n + Δt v_{n+½}
///
/// Constraints per step, one pass per kind of node (internal/constraints.cpp, advance): free
/// nodes; tied node sets, which share one acceleration; rigid bodies, which move with 6 DOF
/// (exact rotation of their nodes). In each pass the fixed / prescribed dofs of those nodes
/// overwrite v_{n+½} and their reaction force is recorded. Element forces are computed per element into a private array and
/// then gathered per node in a fixed order, so results do not depend on the number of threads.
///
/// Usage (tests and run()):
///   solve::Solver s(model);             // throws pipeline::Error(bad_input) on a bad model
///   while (s.time() < t_end) s.step();  // throws nothing; check s.health() for divergence
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "solve/contact.h"
#include "solve/model.h"

namespace solve {

/// Energies at the start of the last step [N·mm = mJ]: time and kinetic of every step, the others
/// (the works up to t_n among them) of the last step that requested them (request_energy).
struct Energies {
  double time = 0;
  /// the mean of the two half-step kinetic energies, ½(½m v_{n−½}² + ½m v_{n+½}²) (every step)
  double kinetic = 0;
  double internal = 0;  ///< strain + hourglass energy (only when requested, see request_energy)
  double contact = 0;   ///< work absorbed by contact forces (penalty springs + contact damping)
  double damping = 0;   ///< work dissipated by mass-proportional damping
  double external = 0;  ///< work of loads and of reaction forces of prescribed / fixed dofs
  /// the central-difference scheme's own term −¼·dt·f_int·(v_{n+½} − v_{n−½}), O(dt²) while the
  /// motion is smooth (solver.cpp)
  double scheme = 0;
  /// kinetic + internal + contact + damping − external + scheme − (its initial value): conserved
  /// exactly, jumps included, for a quadratic strain energy at a constant step; ≈ 0 when healthy
  double balance = 0;
};

/// Everything a later run needs to continue exactly (the restart file content).
struct SolverState {
  double time = 0, dt = 0;
  double dt_contact = 0;  ///< the step the contact stiffness is set with (0: not saved, dt) [ms]
  long step = 0;
  std::vector<double> X, x, v;           ///< #nodes×3 reference positions, positions, v_{n−½}
  std::vector<double> rigid;             ///< per rigid body: V (3), ω (3)
  double e_contact = 0, e_damping = 0, w_external = 0, e_initial = 0;
  bool e_initial_set = false;
  /// Per contact pair (deck order): ContactPair::history() — friction stick forces, sides of
  /// two-sided masters and the search state (empty: none saved, contact starts afresh).
  std::vector<std::vector<double>> contact_history;
};

class Solver {
 public:
  /// Sets up elements, lumped masses (with mass scaling when control.dt_target > 0), constraints,
  /// contact pairs and the stable step. Applies initial velocities. @throws pipeline::Error(bad_input).
  /// @param start_x  #nodes×3 positions the run will start from (the state set_state will be given),
  ///                 where the ties are matched; nullptr: the model's reference geometry.
  ///                 @throws pipeline::Error(bad_input) if its node count is not the model's.
  explicit Solver(Model model, const std::vector<double>* start_x = nullptr);
  ~Solver();
  Solver(const Solver&) = delete;
  Solver& operator=(const Solver&) = delete;

  /// Advances one step. After it, health() tells whether the state is still sound.
  void step();
  /// Steps until time() ≥ t (never shortens a step, so a stopped and restarted run is identical).
  void run_until(double t);
  /// Makes the next step() compute the internal energy too (Energies::internal, balance).
  void request_energy() { want_energy_ = true; }
  /// "" when healthy; otherwise why the run must stop (NaN, inverted element, energy, penetration).
  const std::string& health() const { return health_; }

  const Model& model() const;
  double time() const;
  double dt() const;
  long steps() const;
  double stable_dt() const;          ///< stable step from the elements not held (before dt_scale) [ms]
  /// The step the contact stiffness k = s·m*/Δt² is set with [ms]: dt_scale times the stable
  /// step of every element, held by `fixed` or not; dt() is longer where held elements alone
  /// bounded the step (up to the contact pairs' limit, solver.cpp choose_step).
  double contact_dt() const;
  /// The part whose element set the stable step at the start ("" when only rigid parts): the one
  /// to look at when a run needs far more steps than expected (an E in Pa read as MPa).
  const std::string& step_limiting_part() const;
  double added_mass() const;         ///< mass added by mass scaling [g]
  double physical_mass() const;      ///< the parts' own mass, without mass scaling [g]
  double total_mass() const;         ///< [g]
  const std::vector<double>& x() const;      ///< #nodes×3 current positions [mm]
  const std::vector<double>& v() const;      ///< #nodes×3 velocities v_{n−½} [mm/ms]
  const std::vector<double>& mass() const;   ///< #nodes lumped masses [g]
  /// #nodes×3 internal (element) forces of the last step, computed on the positions before it [N]
  const std::vector<double>& internal_force() const;
  std::vector<double> displacement() const;  ///< x − X [mm]
  const Energies& energies() const;          ///< of the last step
  double internal_energy() const;            ///< of the current positions [mJ]
  std::vector<double> von_mises() const;     ///< nodal average of element von Mises stress [MPa]
  std::vector<double> contact_pressure() const;  ///< sum over pairs, #nodes [MPa]
  std::vector<double> contact_shear() const;     ///< sum over pairs, #nodes [MPa]
  const std::vector<ContactPair>& contacts() const;
  double max_penetration() const;            ///< over all pairs, last step [mm]
  /// Sum of reaction (constraint) forces on the nodes of a group in the last step [N].
  std::array<double, 3> reaction(const std::string& group) const;
  /// Sum of element (internal) forces on the nodes of a group in the last step [N]: the force the
  /// rest of the body transmits through this node set.
  std::array<double, 3> section_force(const std::string& group) const;

  SolverState state() const;
  /// Continues from a saved state (same mesh: node count and reference positions checked to
  /// 1e-9, throws bad_input otherwise). reset_time: time and step counter start at 0;
  /// reset_velocity: start at rest but for the model's initial velocities, and the energy
  /// balance starts afresh (as it does with reset_time). Ties keep the
  /// partners matched at construction (give the state's positions as start_x there); tied nodes
  /// get their mass-weighted mean velocity.
  void set_state(const SolverState& s, bool reset_time = false, bool reset_velocity = false);

 private:
  struct Impl;
  std::unique_ptr<Impl> p_;
  std::string health_;
  bool want_energy_ = false;
};

}  // namespace solve
