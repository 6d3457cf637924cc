#pragma once
/// The finite-element model the solver runs: mesh (nodes, parts of elements, named node groups and
/// surfaces) plus everything the deck assigns (materials, constraints, loads, contact, control).
/// Built by load_model (from .msh + JSON deck) or in memory by make_block (tests).
/// Units: mm, ms, g, N, MPa.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "solve/contact.h"

namespace solve {

/// Element types; node orderings are gmsh's (prism: bottom triangle 0-1-2, top 3-4-5).
enum class ElementType { tet4, wedge6, hex8, tri3, quad4 };
int nodes_per_element(ElementType t);
bool is_membrane(ElementType t);
const char* element_name(ElementType t);

struct Material {
  std::string name;
  double density = 0;  ///< [g/mm³] > 0
  double E = 0;        ///< Young's modulus [MPa] > 0
  double nu = 0;       ///< Poisson's ratio, [0, 0.5)
  bool rigid = false;  ///< nodes of rigid parts move as one rigid body
};

/// A set of elements of one type and one material (one physical group of the mesh).
struct Part {
  std::string name;        ///< physical group name
  ElementType type = ElementType::wedge6;
  int material = -1;       ///< index into Model::materials
  double thickness = 0;    ///< membranes only [mm]
  std::vector<int> conn;   ///< #elements×nodes_per_element node indices
  std::size_t size() const { return conn.size() / nodes_per_element(type); }
};

/// Piecewise linear function of time, constant beyond its end points.
struct Curve {
  std::vector<double> t, value;
  double at(double time) const;
  static Curve constant(double v) { return Curve{{0.0}, {v}}; }
};

enum class BcKind { fixed, velocity, displacement };
struct NodeBc {
  std::string group;
  int dof = 0;          ///< 0 x, 1 y, 2 z
  BcKind kind = BcKind::fixed;
  Curve curve;          ///< velocity [mm/ms] or displacement [mm]; unused for fixed
};
struct Load {
  std::string group;
  int dof = 0;
  Curve curve;          ///< total force on the group [N], split equally among its nodes
};
struct InitialVelocity {
  std::string group;
  std::array<double, 3> v{0, 0, 0};  ///< [mm/ms]
};
struct Tie {
  std::string name, group_a, group_b;
  double tolerance = 0.01;  ///< [mm]
};
struct ContactDef {
  std::string name, slave, master;
  double penalty_scale = 0.1, damping_ratio = 0.0, friction = 0.0;
  bool two_sided = false;
};
struct InitialState {
  std::string file;          ///< empty: start from the reference geometry at rest
  bool reset_time = false, reset_velocity = false;
};
struct Control {
  double end_time = 0;              ///< [ms]
  double damping_alpha = 0;         ///< [1/ms]
  double dt_scale = 0.9;
  double dt_target = 0;             ///< [ms], 0: no mass scaling
  int dt_update_interval = 100;
  double hourglass = 0.1;
  double output_interval = 0;       ///< [ms], 0: end_time/10
  double history_interval = 0;      ///< [ms], 0: output_interval/10
  double energy_tolerance = 0.05;
  double penetration_tolerance = 1.0;  ///< [mm]
};
struct OutputSpec {
  std::vector<std::string> node_data{"displacement", "velocity", "contact_pressure", "contact_shear",
                                     "von_mises"};
  std::vector<std::string> history_groups;
};

struct Model {
  std::string name = "model";           ///< file names for messages ("a.msh + a.json")
  std::vector<double> X;                ///< #nodes×3 reference coordinates [mm]
  std::vector<long> node_tags;          ///< gmsh tag of each node (for output), #nodes
  std::map<std::string, std::vector<int>> node_groups;                ///< sorted, unique
  std::map<std::string, std::vector<std::array<int, 3>>> surfaces;    ///< triangles per group
  std::vector<Material> materials;
  std::vector<Part> parts;
  std::vector<NodeBc> bcs;
  std::vector<Load> loads;
  std::vector<InitialVelocity> initial_velocities;
  std::vector<Tie> ties;
  std::vector<ContactDef> contacts;
  InitialState initial_state;
  Control control;
  OutputSpec output;

  std::size_t n_nodes() const { return X.size() / 3; }
  /// The gmsh tag of node `i` (i + 1 for a model built without tags), as outputs and messages name it.
  long node_tag(std::size_t i) const { return node_tags.empty() ? long(i) + 1 : node_tags[i]; }
  /// Node ids of a group; throws pipeline::Error(bad_input) naming the model if absent.
  const std::vector<int>& group(const std::string& name) const;
  /// Triangles of a surface group; throws bad_input if absent or empty.
  const std::vector<std::array<int, 3>>& surface(const std::string& name) const;
};

/// Checks the model is consistent (groups exist, materials valid, node ids in range, elements of
/// positive volume, every node of a part has mass, ...). Throws pipeline::Error(bad_input) with one
/// line naming the model and the problem.
void check_model(const Model& m);

}  // namespace solve
