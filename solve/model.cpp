#include "solve/model.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "pipeline/error.h"
#include "pipeline/units.h"

namespace solve {

int nodes_per_element(ElementType t) {
  switch (t) {
    case ElementType::tet4: return 4;
    case ElementType::wedge6: return 6;
    case ElementType::hex8: return 8;
    case ElementType::tri3: return 3;
    case ElementType::quad4: return 4;
  }
  return 0;
}

bool is_membrane(ElementType t) { return t == ElementType::tri3 || t == ElementType::quad4; }

const char* element_name(ElementType t) {
  switch (t) {
    case ElementType::tet4: return "tet4";
    case ElementType::wedge6: return "wedge6";
    case ElementType::hex8: return "hex8";
    case ElementType::tri3: return "tri3";
    case ElementType::quad4: return "quad4";
  }
  return "?";
}

double Curve::at(double time) const {
  if (t.empty()) return 0.0;
  if (time <= t.front()) return value.front();
  if (time >= t.back()) return value.back();
  auto it = std::upper_bound(t.begin(), t.end(), time);
  std::size_t i = std::size_t(it - t.begin());  // t[i-1] <= time < t[i], so t1 > t0 (a step is a jump past it)
  double t0 = t[i - 1], t1 = t[i];
  double w = (time - t0) / (t1 - t0);
  return (1 - w) * value[i - 1] + w * value[i];
}

const std::vector<int>& Model::group(const std::string& g) const {
  auto it = node_groups.find(g);
  if (it == node_groups.end()) throw pipeline::bad_input(name, "no physical group named '" + g + "'");
  return it->second;
}

const std::vector<std::array<int, 3>>& Model::surface(const std::string& g) const {
  auto it = surfaces.find(g);
  if (it == surfaces.end() || it->second.empty())
    throw pipeline::bad_input(name, "group '" + g + "' has no surface facets (2D elements or 3D boundary)");
  return it->second;
}

void check_model(const Model& m) {
  auto bad = [&](const std::string& what) { return pipeline::bad_input(m.name, what); };
  const std::size_t n = m.n_nodes();
  if (n == 0) throw bad("no nodes");
  for (std::size_t i = 0; i < m.X.size(); ++i)
    if (!std::isfinite(m.X[i])) throw bad("node " + std::to_string(m.node_tag(i / 3)) + " has a non-finite coordinate");
  // A model that holds a head (group head_skin, as assemble writes it) in metres or cm ran, without
  // a word, 1000 or 10 times the steps of the same model in mm: medium_onesize's stage I in metres
  // started 48.7 million steps with an ETA of 16 days. Its head must have a head's size in mm.
  if (const auto g = m.node_groups.find("head_skin"); g != m.node_groups.end() && !g->second.empty()) {
    std::vector<const double*> skin;  // each node's x, y, z, as largest_extent reads a point
    for (int id : g->second) {
      if (id < 0 || std::size_t(id) >= n) throw bad("group 'head_skin': node id out of range");
      skin.push_back(&m.X[3 * std::size_t(id)]);
    }
    pipeline::require_mm(m.name, pipeline::largest_extent(skin), "head");
  }
  if (m.parts.empty()) throw bad("no parts: the deck assigns no material to any element group");
  for (const auto& mat : m.materials)
    if (const std::string why = pipeline::why_material_unusable(mat.density, mat.E, mat.nu); !why.empty())
      throw bad("material '" + mat.name + "': " + why);
  std::vector<char> has_mass(n, 0);
  for (const auto& p : m.parts) {
    if (p.material < 0 || p.material >= int(m.materials.size()))
      throw bad("part '" + p.name + "': no material");
    // A membrane thicker than 100 mm is no membrane (a strap is 1 mm): 1e9 ran with exit 0.
    if (is_membrane(p.type) && !(p.thickness > 0 && p.thickness <= 100))
      throw bad("part '" + p.name + "': membrane needs a thickness in (0, 100] mm");
    if (p.conn.empty()) throw bad("part '" + p.name + "': no elements");
    for (int id : p.conn) {
      if (id < 0 || std::size_t(id) >= n) throw bad("part '" + p.name + "': node id out of range");
      has_mass[id] = 1;
    }
  }
  // A group named by a deck entry: the message names the entry too (it named only the group).
  auto check_group = [&](const std::string& g, const std::string& entry) {
    if (!m.node_groups.count(g)) throw bad(entry + ": no physical group named '" + g + "'");
  };
  for (const auto& b : m.bcs) {
    check_group(b.group, (b.kind == BcKind::fixed ? "fixed[" : "prescribed[") + b.group + "]");
    if (b.dof < 0 || b.dof > 2) throw bad("boundary condition on '" + b.group + "': dof must be x, y or z");
  }
  for (const auto& l : m.loads) check_group(l.group, "loads[" + l.group + "]");
  for (const auto& iv : m.initial_velocities) check_group(iv.group, "initial_velocity[" + iv.group + "]");
  std::set<std::string> names;  // a second tie or contact of one name is a copy-paste slip
  std::map<std::pair<std::string, std::string>, std::string> tied_pairs;
  for (const auto& t : m.ties) {
    check_group(t.group_a, "tie '" + t.name + "'");
    check_group(t.group_b, "tie '" + t.name + "'");
    if (!(t.tolerance > 0)) throw bad("tie '" + t.name + "': tolerance must be > 0 [mm]");
    if (!names.insert("tie " + t.name).second) throw bad("two ties named '" + t.name + "'");
    // The same two groups tied twice under two names was accepted, as a contact pair twice was.
    const auto [a, b] = std::minmax(t.group_a, t.group_b);
    if (const auto [it, first] = tied_pairs.emplace(std::make_pair(a, b), t.name); !first)
      throw bad("ties '" + it->second + "' and '" + t.name + "' both tie '" + a + "' to '" + b + "': a pair once");
  }
  // The same slave group on the same master surface twice doubled the penalty without a word.
  std::map<std::pair<std::string, std::string>, std::string> pair_names;
  for (const auto& c : m.contacts) {
    check_group(c.slave, "contact '" + c.name + "'");
    check_group(c.master, "contact '" + c.name + "'");
    // Self-contact is not modelled: a group on itself gave no force and made each step 15 times
    // slower, exit 0 (a tie of a group to itself is refused too).
    if (c.slave == c.master)
      throw bad("contact '" + c.name + "': slave and master are both '" + c.slave + "': self-contact is not modelled");
    m.surface(c.master);
    if (!(c.penalty_scale > 0 && c.penalty_scale <= 1))
      throw bad("contact '" + c.name + "': penalty_scale must be in (0, 1]");
    // Coulomb coefficients of skin on fabric or silicone are 0.2-1; 1e9 ran with exit 0.
    if (!(c.friction >= 0 && c.friction <= 2)) throw bad("contact '" + c.name + "': friction must be in [0, 2]");
    if (!names.insert("contact " + c.name).second) throw bad("two contacts named '" + c.name + "'");
    const auto [it, first] = pair_names.emplace(std::make_pair(c.slave, c.master), c.name);
    if (!first)
      throw bad("contacts '" + it->second + "' and '" + c.name + "' both press '" + c.slave + "' on '" + c.master +
                "': a pair once, or its penalty counts twice");
  }
  for (const auto& g : m.output.history_groups) check_group(g, "output.history_groups");
  // The first node of `group` that no part gives mass is refused, named as outputs name it.
  const auto require_mass = [&](const std::string& group, const std::string& entry, const std::string& why) {
    for (int id : m.group(group))
      if (!has_mass[id])
        throw bad(entry + "node " + std::to_string(m.node_tag(std::size_t(id))) + " belongs to no part (no mass)" + why);
  };
  for (const auto& c : m.contacts) require_mass(c.slave, "contact '" + c.name + "': slave ", "");
  // A node without mass keeps no velocity (the update sets it to 0): a load's share on it did no
  // work and vanished, exit 0 (a deck that left the strap out of its parts lost all 10 N).
  for (const auto& l : m.loads)
    require_mass(l.group, "loads[" + l.group + "]: ",
                 ": its share of the load would be lost; give the group's elements a part");
  for (const auto& iv : m.initial_velocities)
    require_mass(iv.group, "initial_velocity[" + iv.group + "]: ", ": it cannot move");
  const Control& c = m.control;
  if (!(c.end_time > 0)) throw bad("control.end_time must be > 0");
  if (!(c.damping_alpha >= 0 && c.damping_alpha <= pipeline::max_damping_alpha_per_ms))
    throw bad("control.damping_alpha must be in [0, " + pipeline::format_number(pipeline::max_damping_alpha_per_ms) +
              "] [1/ms]");
  if (!(c.dt_scale > 0 && c.dt_scale <= 1)) throw bad("control.dt_scale must be in (0, 1]");
  if (!(c.dt_target >= 0)) throw bad("control.dt_target must be >= 0");
  if (c.dt_update_interval < 1) throw bad("control.dt_update_interval must be >= 1");
  if (!(c.hourglass >= 0 && c.hourglass <= 1)) throw bad("control.hourglass must be in [0, 1]");
  if (!(c.output_interval >= 0) || !(c.history_interval >= 0)) throw bad("output intervals must be >= 0");
  // a fraction of the largest energy: above 1 the guard never trips
  if (!(c.energy_tolerance > 0 && c.energy_tolerance <= 1)) throw bad("control.energy_tolerance must be in (0, 1]");
  if (!(c.penetration_tolerance > 0)) throw bad("control.penetration_tolerance must be > 0");
  static const char* known[] = {"displacement", "velocity", "contact_pressure", "contact_shear", "von_mises"};
  for (const auto& d : m.output.node_data)
    if (std::find_if(std::begin(known), std::end(known), [&](const char* k) { return d == k; }) == std::end(known))
      throw bad("output.node_data: unknown field '" + d + "'");
}

}  // namespace solve
