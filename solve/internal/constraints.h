#pragma once
/// Kinematic constraints of the integrator (internal to solve/): tied node sets, rigid bodies,
/// fixed and prescribed dofs, and the velocity/position update that honours them.
///
/// Node sets are merged with a union–find: the nodes of a rigid part (and any rigid parts or ties
/// sharing nodes with it) form one rigid body; other nodes linked by ties form a tie group whose
/// nodes share one velocity (one acceleration from the summed force and mass).
#include <array>
#include <vector>

#include "solve/model.h"

namespace solve::internal {

struct RigidBody {
  std::vector<int> nodes;
  double M = 0;                        ///< [g]
  std::array<int, 3> bc{-1, -1, -1};   ///< index into Model::bcs per translation dof, -1 free
  std::array<int, 3> bc_node{-1, -1, -1};  ///< node whose displacement a displacement BC prescribes
  bool rotation_locked = false;        ///< true as soon as any BC touches the body
  std::array<double, 3> V{0, 0, 0}, w{0, 0, 0};  ///< velocity of the mass centre, angular velocity
};

struct TieGroup {
  std::vector<int> nodes;
  std::array<int, 3> bc{-1, -1, -1};
  std::array<int, 3> bc_node{-1, -1, -1};
};

struct Constraints {
  std::vector<int> free_nodes;   ///< neither tied nor rigid
  std::vector<int> bc;           ///< #nodes×3 index into Model::bcs, -1 none (free nodes)
  std::vector<TieGroup> ties;
  std::vector<RigidBody> bodies;
};

/// @param rigid_node #nodes flags (node of a rigid part)
/// @param x          #nodes×3 positions the ties are matched at: where the run starts (the model's
///                   reference geometry, or an initial state's deformed one: Stage II ties strap ends
///                   that Stage I moved onto the respirator)
/// @throws pipeline::Error(bad_input) if a tie finds no partner within its tolerance.
Constraints build_constraints(const Model& m, const std::vector<char>& rigid_node, const std::vector<double>& mass,
                              const std::vector<double>& x);

/// Makes initial velocities consistent: tied nodes get their mass-weighted mean velocity, rigid
/// bodies the mean translation (no initial spin).
void init_constraint_velocities(Constraints& c, const std::vector<double>& x, const std::vector<double>& mass,
                                std::vector<double>& v);

/// One central-difference update of v (v_{n−½} → v_{n+½}) and x (x_n → x_{n+1}) under the
/// constraints, with damping c = α·m. reac gets the constraint forces of fixed/prescribed dofs [N].
void advance(Constraints& c, const Model& m, const std::vector<double>& X, const std::vector<double>& mass,
             const std::vector<double>& fint, const std::vector<double>& fext, const std::vector<double>& fcon,
             double alpha, double t, double dt, std::vector<double>& x, std::vector<double>& v,
             std::vector<double>& reac);

/// Rigid body velocities (V, ω per body) for the restart state, and back.
std::vector<double> rigid_velocities(const Constraints& c);
void set_rigid_velocities(Constraints& c, const std::vector<double>& rv);

}  // namespace solve::internal
