#include "solve/load_model.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"
#include "pipeline/read_json.h"
#include "pipeline/read_msh.h"
#include "pipeline/units.h"

namespace solve {
namespace {

using json = nlohmann::json;

// Outward faces of the solids (gmsh node orderings; checked on the reference elements).
const std::vector<std::vector<int>>& solid_faces(ElementType t) {
  static const std::vector<std::vector<int>> tet = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  static const std::vector<std::vector<int>> hex = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                    {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  static const std::vector<std::vector<int>> wedge = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}};
  return t == ElementType::tet4 ? tet : t == ElementType::hex8 ? hex : wedge;
}

void add_polygon(std::vector<std::array<int, 3>>& tris, const std::vector<int>& f) {
  tris.push_back({f[0], f[1], f[2]});
  if (f.size() == 4) tris.push_back({f[0], f[2], f[3]});
}

// Boundary faces (appearing once) of solid parts, outward, as polygons of 3 or 4 nodes.
std::vector<std::vector<int>> boundary_polygons(const std::vector<const Part*>& parts) {
  std::map<std::vector<int>, std::pair<int, std::vector<int>>> faces;
  for (const Part* p : parts) {
    if (is_membrane(p->type)) continue;
    const int nn = nodes_per_element(p->type);
    for (std::size_t e = 0; e < p->size(); ++e)
      for (const auto& lf : solid_faces(p->type)) {
        std::vector<int> f;
        for (int a : lf) f.push_back(p->conn[e * nn + a]);
        std::vector<int> key = f;
        std::sort(key.begin(), key.end());
        auto& entry = faces[key];
        entry.first++;
        entry.second = f;
      }
  }
  std::vector<std::vector<int>> polygons;
  for (const auto& [key, entry] : faces)
    if (entry.first == 1) polygons.push_back(entry.second);
  return polygons;
}

// Boundary faces of the solid parts of a group, as outward triangles.
std::vector<std::array<int, 3>> boundary_of(const std::vector<const Part*>& parts) {
  std::vector<std::array<int, 3>> tris;
  for (const auto& f : boundary_polygons(parts)) add_polygon(tris, f);
  return tris;
}

bool gmsh_type(int t, ElementType* out) {
  switch (t) {
    case 2: *out = ElementType::tri3; return true;
    case 3: *out = ElementType::quad4; return true;
    case 4: *out = ElementType::tet4; return true;
    case 5: *out = ElementType::hex8; return true;
    case 6: *out = ElementType::wedge6; return true;
  }
  return false;
}

// ---- deck helpers: every error names the deck and the key ----
struct Deck {
  const json& j;
  std::string name;
  pipeline::Error bad(const std::string& what) const { return pipeline::bad_input(name, what); }
};

double num(const Deck& d, const json& o, const std::string& key, const std::string& where, double def, bool required) {
  if (!o.contains(key)) {
    if (required) throw d.bad(where + ": missing '" + key + "'");
    return def;
  }
  if (!o[key].is_number()) throw d.bad(where + "." + key + ": expected a number");
  return o[key].get<double>();
}
std::string str(const Deck& d, const json& o, const std::string& key, const std::string& where) {
  if (!o.contains(key) || !o[key].is_string()) throw d.bad(where + ": missing or non-string '" + key + "'");
  return o[key].get<std::string>();
}
bool flag(const Deck& d, const json& o, const std::string& key, const std::string& where, bool def) {
  if (!o.contains(key)) return def;
  if (!o[key].is_boolean()) throw d.bad(where + "." + key + ": expected true or false");
  return o[key].get<bool>();
}
int dof_of(const Deck& d, const std::string& s, const std::string& where) {
  if (s == "x") return 0;
  if (s == "y") return 1;
  if (s == "z") return 2;
  throw d.bad(where + ".dof: expected \"x\", \"y\" or \"z\", got \"" + s + "\"");
}
Curve curve_of(const Deck& d, const json& o, const std::string& where) {
  if (!o.contains("curve") || !o["curve"].is_array())
    throw d.bad(where + ": missing 'curve' ([[t, value], ...])");
  if (o["curve"].empty()) throw d.bad(where + ".curve: empty, expected at least one point [t, value]");
  Curve c;
  for (const auto& p : o["curve"]) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
      throw d.bad(where + ".curve: each point must be [t, value]");
    const double t = p[0].get<double>();
    if (!c.t.empty() && t < c.t.back()) throw d.bad(where + ".curve: times must not decrease");
    c.t.push_back(t);
    c.value.push_back(p[1].get<double>());
  }
  return c;
}
// Every key a deck object may hold, or one starting with "_" (a comment). The optional keys have
// defaults, so a misspelt one ("frction": 0.3) was read as absent and the run used friction 0.
void require_known_keys(const Deck& d, const json& o, const std::string& where, const std::set<std::string>& keys) {
  if (!o.is_object()) throw d.bad(where + ": expected an object");
  if (const std::string key = pipeline::first_unknown_key(o, keys); !key.empty())
    throw d.bad(where + "." + key + ": unknown key");
}
const json& array_of(const Deck& d, const std::string& key) {
  static const json empty = json::array();
  if (!d.j.contains(key)) return empty;
  if (!d.j[key].is_array()) throw d.bad("'" + key + "' must be an array");
  return d.j[key];
}

// A one-sided contact master given as 2D elements must face out of the solid whose boundary it
// lies on: flipped triangles (a model edited by hand) pushed slave points through from the wrong
// side, which showed only as a 6 mm "penetration" at the first step, or not at all where no slave
// lay over them. `boundary` holds every solid's outward boundary faces; triangles on none are
// not judged (a free membrane has no outside).
void require_masters_face_out(const Deck& d, const Model& m, const std::vector<std::vector<int>>& boundary) {
  std::map<std::array<int, 3>, const std::vector<int>*> face_of;  // any 3 nodes of a face → the face
  for (const auto& f : boundary)
    for (std::size_t skip = 0; skip < (f.size() == 4 ? 4u : 1u); ++skip) {
      std::array<int, 3> key{};
      for (std::size_t k = 0, i = 0; k < f.size(); ++k)
        if (f.size() != 4 || k != skip) key[i++] = f[k];
      std::sort(key.begin(), key.end());
      face_of.emplace(key, &f);
    }
  for (const auto& c : m.contacts) {
    if (c.two_sided || !m.surfaces.count(c.master)) continue;
    const auto& tris = m.surfaces.at(c.master);
    std::size_t flipped = 0;
    std::string first;
    for (const auto& t : tris) {
      std::array<int, 3> key = t;
      std::sort(key.begin(), key.end());
      const auto it = face_of.find(key);
      if (it == face_of.end()) continue;
      const std::vector<int>& f = *it->second;
      const long n = long(f.size());
      const auto at = [&](int node) { return long(std::find(f.begin(), f.end(), node) - f.begin()); };
      const long ia = at(t[0]), ib = at(t[1]), ic = at(t[2]);
      if ((ib - ia + n) % n < (ic - ia + n) % n) continue;  // the face's own turning sense: outward
      if (flipped++ == 0) {
        double x[3] = {0, 0, 0};
        for (int v : t)
          for (int k = 0; k < 3; ++k) x[k] += m.X[3 * std::size_t(v) + std::size_t(k)] / 3;
        first = pipeline::format_position_mm(x[0], x[1], x[2]);
      }
    }
    if (flipped > 0)
      throw d.bad("contact '" + c.name + "': " + std::to_string(flipped) + " of the " + std::to_string(tris.size()) +
                  " triangles of master '" + c.master + "' face into the solid they lie on (the first centred at " +
                  first + "): a master faces outward by the right-hand rule (or give the pair two_sided)");
  }
}

}  // namespace

Model read_msh(const std::string& path) {
  const pipeline::MshFile file = pipeline::read_msh(path);
  if (file.groups.empty())
    throw pipeline::bad_input(path, "no physical groups: the solver addresses the mesh by named groups");
  Model m;
  m.name = path;
  m.node_tags.assign(file.node_tags.begin(), file.node_tags.end());
  m.X = file.xyz;
  for (const pipeline::MshGroup& g : file.groups) {
    const std::string name = g.name.empty() ? std::to_string(g.dim) + ":" + std::to_string(g.tag) : g.name;  // unnamed: "dim:tag"
    auto& nodes = m.node_groups[name];
    for (const pipeline::MshElements& e : g.elements) {
      nodes.insert(nodes.end(), e.conn.begin(), e.conn.end());
      ElementType et;
      if ((g.dim == 2 || g.dim == 3) && gmsh_type(e.gmsh_type, &et)) {
        Part p;
        p.name = name;
        p.type = et;
        p.conn = e.conn;
        m.parts.push_back(std::move(p));
      }
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  }
  // Surfaces: 2D elements of a group; else the boundary of its 3D elements.
  std::map<std::string, std::vector<const Part*>> solids;
  for (const auto& p : m.parts) {
    if (is_membrane(p.type)) {
      const int nn = nodes_per_element(p.type);
      for (std::size_t e = 0; e < p.size(); ++e)
        add_polygon(m.surfaces[p.name], std::vector<int>(p.conn.begin() + e * nn, p.conn.begin() + (e + 1) * nn));
    } else {
      solids[p.name].push_back(&p);
    }
  }
  for (const auto& [name, parts] : solids)
    if (!m.surfaces.count(name)) m.surfaces[name] = boundary_of(parts);
  return m;
}

void apply_deck_json(Model& m, const json& j, const std::string& deck_name);

void apply_deck(Model& m, const std::string& text, const std::string& deck_name) {
  const json j = pipeline::parse_json(text, deck_name);
  if (!j.is_object()) throw pipeline::bad_input(deck_name, "the deck must be a JSON object");
  try {
    apply_deck_json(m, j, deck_name);
  } catch (const json::exception& e) {
    throw pipeline::bad_input(deck_name, "wrong value type: " + pipeline::json_error_text(e));
  }
}

namespace {

// The deck's "model_check" (written by assemble: the node count and bounding box of the model it
// was made for) against the model read. A case's deck with another case's model ran for 10
// minutes, its strap ends driven to the other model's attachment points, and stage II's ties
// then failed naming a node, not the cause.
void check_deck_model(const Deck& d, const json& o, const Model& m, const std::string& model_name) {
  require_known_keys(d, o, "model_check", {"nodes", "bounds_mm"});
  const double nodes = num(d, o, "nodes", "model_check", 0, true);
  if (!o.contains("bounds_mm") || !o["bounds_mm"].is_array() || o["bounds_mm"].size() != 2)
    throw d.bad("model_check.bounds_mm: expected [[x, y, z], [x, y, z]] (lowest, highest) [mm]");
  std::array<double, 6> made_for;  // lowest x, y, z, then highest, as model_bounds_mm
  for (std::size_t k = 0; k < 6; ++k) made_for[k] = o["bounds_mm"][k / 3].at(k % 3).get<double>();
  const std::array<double, 6> here = model_bounds_mm(m);
  constexpr double tolerance_mm = 1e-3;  // assemble writes the coordinates to 16 digits
  bool same = double(m.n_nodes()) == nodes;
  for (int k = 0; k < 6; ++k) same = same && std::fabs(made_for[std::size_t(k)] - here[std::size_t(k)]) <= tolerance_mm;
  if (same) return;
  const auto box = [](const std::array<double, 6>& b) {
    return pipeline::format_position_mm(b[0], b[1], b[2]) + " to " + pipeline::format_position_mm(b[3], b[4], b[5]);
  };
  // The boxes print to 0.1 mm; a box off by less showed two equal boxes: name the largest gap too.
  double gap = 0;
  int worst = 0;
  for (int k = 0; k < 6; ++k)
    if (std::fabs(made_for[std::size_t(k)] - here[std::size_t(k)]) > gap)
      gap = std::fabs(made_for[std::size_t(k)] - here[std::size_t(k)]), worst = k;
  const std::string box_gap =
      gap > tolerance_mm ? std::string(" (its ") + (worst < 3 ? "lowest " : "highest ") + "xyz"[worst % 3] + " differs by " +
                               pipeline::format_number(gap) + " mm)"
                         : "";
  throw d.bad("made for a model of " + pipeline::format_number(nodes) + " nodes from " + box(made_for) + ", and " +
              model_name + " has " + std::to_string(m.n_nodes()) + " nodes from " + box(here) + box_gap +
              ": the deck of another case, or of an earlier assemble? (assemble writes the model and its decks together)");
}

}  // namespace

std::array<double, 6> model_bounds_mm(const Model& m) {
  std::array<double, 6> b = {1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
  for (std::size_t i = 0; i < m.n_nodes(); ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      b[k] = std::min(b[k], m.X[3 * i + k]);
      b[3 + k] = std::max(b[3 + k], m.X[3 * i + k]);
    }
  return b;
}

void apply_deck_json(Model& m, const json& j, const std::string& deck_name) {
  const Deck d{j, deck_name};
  // Unknown keys first: a misspelt required one ("contol", "Materials") was reported as missing.
  if (const std::string key = pipeline::first_unknown_key(j, {"materials", "parts", "fixed", "prescribed", "loads",
                                                               "initial_velocity", "ties", "contact", "initial_state",
                                                               "control", "output", "model_check"});
      !key.empty())
    throw d.bad("unknown top-level key '" + key + "'");
  // Every solid group of the mesh, before the deck picks its parts, bounds the contact masters
  // (require_masters_face_out); a deck without contact needs no boundary.
  std::vector<std::vector<int>> solid_boundary;
  if (j.contains("contact") && j["contact"].is_array() && !j["contact"].empty()) {
    std::vector<const Part*> mesh_parts;
    for (const Part& p : m.parts) mesh_parts.push_back(&p);
    solid_boundary = boundary_polygons(mesh_parts);
  }
  if (j.contains("model_check")) check_deck_model(d, j["model_check"], m, m.name);
  m.name = m.name + " + " + deck_name;
  // Materials.
  if (!j.contains("materials") || !j["materials"].is_object() || j["materials"].empty())
    throw d.bad("missing 'materials' object");
  m.materials.clear();
  for (const auto& [name, o] : j["materials"].items()) {
    const std::string w = "materials." + name;
    require_known_keys(d, o, w, pipeline::material_keys);
    Material mat;
    mat.name = name;
    mat.density = num(d, o, "density", w, 0, true);
    mat.E = num(d, o, "E", w, 0, true);
    mat.nu = num(d, o, "nu", w, 0, true);
    mat.rigid = flag(d, o, "rigid", w, false);
    m.materials.push_back(mat);
  }
  // Parts.
  std::vector<Part> parts;
  std::set<std::string> used;
  for (const auto& o : array_of(d, "parts")) {
    const std::string g = str(d, o, "group", "parts[]");
    const std::string w = "parts[" + g + "]";
    require_known_keys(d, o, w, {"group", "material", "thickness"});
    if (!used.insert(g).second) throw d.bad(w + ": group appears in two parts");
    auto mi = std::find_if(m.materials.begin(), m.materials.end(),
                           [&](const Material& x) { return x.name == str(d, o, "material", w); });
    if (mi == m.materials.end()) throw d.bad(w + ": unknown material '" + str(d, o, "material", w) + "'");
    bool found = false, has_solid = false;
    for (const auto& p : m.parts) has_solid = has_solid || (p.name == g && !is_membrane(p.type));
    // A thickness given to a solid was ignored without a word: its thickness is its mesh's.
    if (has_solid && o.contains("thickness"))
      throw d.bad(w + ".thickness: group '" + g + "' is solid, its thickness is its mesh's (thickness is for membranes)");
    for (const auto& p : m.parts)
      if (p.name == g && (!has_solid || !is_membrane(p.type))) {  // solids win over their own faces
        Part q = p;
        q.material = int(mi - m.materials.begin());
        if (is_membrane(q.type)) q.thickness = num(d, o, "thickness", w, 0, true);
        parts.push_back(std::move(q));
        found = true;
      }
    if (!found) throw d.bad(w + ": the mesh has no group '" + g + "' with 2D or 3D elements");
  }
  m.parts = std::move(parts);
  // Constraints and loads.
  m.bcs.clear();
  for (const auto& o : array_of(d, "fixed")) {
    const std::string g = str(d, o, "group", "fixed[]");
    require_known_keys(d, o, "fixed[" + g + "]", {"group", "dofs"});
    const std::string dofs = o.contains("dofs") ? str(d, o, "dofs", "fixed[" + g + "]") : "xyz";
    // "" fixed nothing without a word, "xxx" fixed x three times
    if (dofs.empty() || std::set<char>(dofs.begin(), dofs.end()).size() != dofs.size())
      throw d.bad("fixed[" + g + "].dofs: '" + dofs + "', expected some of x, y, z, each once");
    for (char c : dofs) m.bcs.push_back({g, dof_of(d, std::string(1, c), "fixed[" + g + "]"), BcKind::fixed, {}});
  }
  for (const auto& o : array_of(d, "prescribed")) {
    const std::string g = str(d, o, "group", "prescribed[]");
    const std::string w = "prescribed[" + g + "]";
    require_known_keys(d, o, w, {"group", "type", "dof", "curve"});
    const std::string type = str(d, o, "type", w);
    if (type != "velocity" && type != "displacement") throw d.bad(w + ".type: expected \"velocity\" or \"displacement\"");
    m.bcs.push_back({g, dof_of(d, str(d, o, "dof", w), w), type == "velocity" ? BcKind::velocity : BcKind::displacement,
                     curve_of(d, o, w)});
  }
  m.loads.clear();
  for (const auto& o : array_of(d, "loads")) {
    const std::string g = str(d, o, "group", "loads[]");
    require_known_keys(d, o, "loads[" + g + "]", {"group", "dof", "curve"});
    m.loads.push_back({g, dof_of(d, str(d, o, "dof", "loads[" + g + "]"), "loads[" + g + "]"), curve_of(d, o, "loads[" + g + "]")});
  }
  m.initial_velocities.clear();
  for (const auto& o : array_of(d, "initial_velocity")) {
    InitialVelocity iv;
    iv.group = str(d, o, "group", "initial_velocity[]");
    require_known_keys(d, o, "initial_velocity[" + iv.group + "]", {"group", "velocity"});
    if (!o.contains("velocity") || !o["velocity"].is_array() || o["velocity"].size() != 3)
      throw d.bad("initial_velocity[" + iv.group + "]: 'velocity' must be [vx, vy, vz]");
    for (int k = 0; k < 3; ++k) iv.v[k] = o["velocity"][k].get<double>();
    m.initial_velocities.push_back(iv);
  }
  m.ties.clear();
  for (const auto& o : array_of(d, "ties")) {
    Tie t;
    t.group_a = str(d, o, "group_a", "ties[]");
    t.group_b = str(d, o, "group_b", "ties[]");
    t.name = o.contains("name") ? str(d, o, "name", "ties[]") : t.group_a + "-" + t.group_b;
    require_known_keys(d, o, "ties[" + t.name + "]", {"group_a", "group_b", "name", "tolerance"});
    t.tolerance = num(d, o, "tolerance", "ties[" + t.name + "]", 0.01, false);
    // (it searched each node's partner among the group's other nodes and named the same group twice)
    if (t.group_a == t.group_b) throw d.bad("ties[" + t.name + "]: ties group '" + t.group_a + "' to itself");
    m.ties.push_back(t);
  }
  m.contacts.clear();
  for (const auto& o : array_of(d, "contact")) {
    ContactDef c;
    c.slave = str(d, o, "slave", "contact[]");
    c.master = str(d, o, "master", "contact[]");
    c.name = o.contains("name") ? str(d, o, "name", "contact[]") : c.slave + "_on_" + c.master;
    const std::string w = "contact[" + c.name + "]";
    require_known_keys(d, o, w, {"slave", "master", "name", "penalty_scale", "damping_ratio", "friction", "two_sided"});
    c.penalty_scale = num(d, o, "penalty_scale", w, 0.1, false);
    c.damping_ratio = num(d, o, "damping_ratio", w, 0.0, false);
    c.friction = num(d, o, "friction", w, 0.0, false);
    c.two_sided = flag(d, o, "two_sided", w, false);
    m.contacts.push_back(c);
  }
  if (j.contains("initial_state")) {
    const json& o = j["initial_state"];
    require_known_keys(d, o, "initial_state", {"file", "reset_time", "reset_velocity"});
    m.initial_state.file = str(d, o, "file", "initial_state");
    if (m.initial_state.file.empty()) throw d.bad("initial_state.file: empty (leave initial_state out to start at rest)");
    m.initial_state.reset_time = flag(d, o, "reset_time", "initial_state", false);
    m.initial_state.reset_velocity = flag(d, o, "reset_velocity", "initial_state", false);
  }
  if (!j.contains("control") || !j["control"].is_object()) throw d.bad("missing 'control' object (end_time at least)");
  const json& c = j["control"];
  require_known_keys(d, c, "control",  // before the values: "end_time_ms" was "missing 'end_time'"
                     {"end_time", "damping_alpha", "dt_scale", "dt_target", "dt_update_interval", "hourglass",
                      "output_interval", "history_interval", "energy_tolerance", "penetration_tolerance"});
  Control& k = m.control;
  k.end_time = num(d, c, "end_time", "control", 0, true);
  k.damping_alpha = num(d, c, "damping_alpha", "control", 0, false);
  k.dt_scale = num(d, c, "dt_scale", "control", 0.9, false);
  k.dt_target = num(d, c, "dt_target", "control", 0, false);
  const double interval = num(d, c, "dt_update_interval", "control", 100, false);
  if (interval != std::floor(interval) || !(std::fabs(interval) < 1e9))  // 1.5 was read as 1
    throw d.bad("control.dt_update_interval: " + pipeline::format_number(interval) + ", expected a whole number of steps");
  k.dt_update_interval = int(interval);
  k.hourglass = num(d, c, "hourglass", "control", 0.1, false);
  k.output_interval = num(d, c, "output_interval", "control", 0, false);
  k.history_interval = num(d, c, "history_interval", "control", 0, false);
  k.energy_tolerance = num(d, c, "energy_tolerance", "control", 0.05, false);
  k.penetration_tolerance = num(d, c, "penetration_tolerance", "control", 1.0, false);
  if (j.contains("output")) {
    const json& o = j["output"];
    require_known_keys(d, o, "output", {"node_data", "history_groups"});
    if (o.contains("node_data")) m.output.node_data = o["node_data"].get<std::vector<std::string>>();
    if (o.contains("history_groups")) m.output.history_groups = o["history_groups"].get<std::vector<std::string>>();
  }
  check_model(m);
  require_masters_face_out(d, m, solid_boundary);
}

Model load_model(const std::string& msh_path, const std::string& deck_path) {
  Model m = read_msh(msh_path);
  apply_deck(m, pipeline::read_text(deck_path), deck_path);
  // a relative initial_state path is relative to the deck's directory
  if (!m.initial_state.file.empty() && std::filesystem::path(m.initial_state.file).is_relative())
    m.initial_state.file = (std::filesystem::path(deck_path).parent_path() / m.initial_state.file).string();
  return m;
}

}  // namespace solve
