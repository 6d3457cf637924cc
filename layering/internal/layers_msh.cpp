// Reading and writing FeModel as gmsh .msh through the gmsh API (gmsh knows its own format best;
// one discrete entity + one named physical group per block); the reading is pipeline::read_msh's.
#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <nlohmann/json.hpp>

#include "layering/layers.h"
#include "pipeline/error.h"
#include "pipeline/gmsh_session.h"
#include "pipeline/read_json.h"
#include "pipeline/read_msh.h"
#include "pipeline/require_cheeks_on_their_sides.h"
#include "pipeline/write_gmsh_model.h"

namespace layering {
namespace {

// gmsh element type codes for the element shapes we use.
int gmsh_type(int dim, int npe) {
  if (dim == 0 && npe == 1) return 15;
  if (dim == 1 && npe == 2) return 1;
  if (dim == 2 && npe == 3) return 2;
  if (dim == 2 && npe == 4) return 3;
  if (dim == 3 && npe == 6) return 6;
  if (dim == 3 && npe == 4) return 4;
  return -1;
}

std::string position(const FeModel& m, int node) {
  const Eigen::Vector3d& p = m.nodes[std::size_t(node)];
  return pipeline::format_position_mm(p.x(), p.y(), p.z());
}

}  // namespace

const Block* FeModel::find(const std::string& name) const {
  for (const Block& b : blocks)
    if (b.name == name) return &b;
  return nullptr;
}

FeModel read_fe_model(const std::string& path) {
  const pipeline::MshFile file = pipeline::read_msh(path);
  FeModel m;
  m.nodes.reserve(file.n_nodes());
  for (std::size_t i = 0; i < file.n_nodes(); ++i)
    m.nodes.emplace_back(file.xyz[3 * i], file.xyz[3 * i + 1], file.xyz[3 * i + 2]);
  for (const pipeline::MshGroup& g : file.groups) {
    Block b;
    b.dim = g.dim;
    b.name = g.name.empty() ? "group_" + std::to_string(g.dim) + "_" + std::to_string(g.tag) : g.name;
    b.nodes_per_elem = 0;
    for (const pipeline::MshElements& e : g.elements) {
      if (b.nodes_per_elem && b.nodes_per_elem != e.nodes_per_element)
        throw pipeline::bad_input(path, "group " + b.name + " mixes element types");
      b.nodes_per_elem = e.nodes_per_element;
      b.conn.insert(b.conn.end(), e.conn.begin(), e.conn.end());
    }
    if (b.nodes_per_elem == 0) b.nodes_per_elem = g.dim == 0 ? 1 : g.dim == 1 ? 2 : g.dim == 2 ? 3 : 6;
    m.blocks.push_back(std::move(b));
  }
  if (m.blocks.empty()) throw pipeline::bad_input(path, "no physical group: expected named parts");
  return m;
}

void write_fe_model(const FeModel& m, const std::string& path) {
  pipeline::GmshSession session;
  gmsh::model::add("model");
  // Nodes live on the first block of the highest dimension; elements of any block refer to them.
  int host = 0;
  for (std::size_t i = 0; i < m.blocks.size(); ++i)
    if (m.blocks[i].dim > m.blocks[host].dim) host = int(i);
  for (std::size_t i = 0; i < m.blocks.size(); ++i) gmsh::model::addDiscreteEntity(m.blocks[i].dim, int(i) + 1);
  std::vector<std::size_t> ntags(m.nodes.size());
  std::vector<double> xyz(3 * m.nodes.size());
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    ntags[i] = i + 1;
    for (int k = 0; k < 3; ++k) xyz[3 * i + k] = m.nodes[i][k];
  }
  if (!m.blocks.empty()) gmsh::model::mesh::addNodes(m.blocks[host].dim, host + 1, ntags, xyz);
  std::size_t next = 1;
  for (std::size_t i = 0; i < m.blocks.size(); ++i) {
    const Block& b = m.blocks[i];
    const int type = gmsh_type(b.dim, b.nodes_per_elem);
    if (type < 0) throw pipeline::io_failed(path, "block " + b.name + ": unsupported element shape");
    std::vector<std::size_t> et(b.size()), nt(b.conn.size());
    for (std::size_t e = 0; e < et.size(); ++e) et[e] = next++;
    for (std::size_t k = 0; k < nt.size(); ++k) nt[k] = std::size_t(b.conn[k]) + 1;
    if (!et.empty()) gmsh::model::mesh::addElementsByType(int(i) + 1, type, et, nt);
    gmsh::model::addPhysicalGroup(b.dim, {int(i) + 1}, int(i) + 1);
    gmsh::model::setPhysicalName(b.dim, int(i) + 1, b.name);
  }
  pipeline::write_gmsh_model(path);
}

std::map<std::string, Stack> read_stacks(const std::string& materials_json, const std::string& kind) {
  const nlohmann::json j = pipeline::read_json(materials_json);
  auto parse_stack = [&](const nlohmann::json& a, const std::string& where) {
    Stack s;
    if (!a.is_array() || a.empty()) throw pipeline::bad_input(materials_json, where + ": expected [[material, mm], ...]");
    // The thickest soft tissue over the face is about 20 mm (cheek fat and muscle); a layer over
    // 50 mm is a unit slip (cm, m) and was layered as columns thinned a millionfold. Below 0.1 mm
    // a wedge under the ~6 mm surface triangles is a sliver (and the explicit time step shrinks
    // with it); a 1e-9 mm layer was dropped without a word. The deepest stack in the paper has
    // four tissues; a stack of 1000 layers ran out of memory.
    constexpr double min_layer_mm = 0.1, max_layer_mm = 50;
    constexpr std::size_t max_layers = 10;
    if (a.size() > max_layers)
      throw pipeline::bad_input(materials_json, where + ": " + std::to_string(a.size()) + " layers, expected at most " +
                                                    std::to_string(max_layers));
    for (const auto& l : a) {
      if (!l.is_array() || l.size() != 2 || !l[0].is_string() || !l[1].is_number() ||
          !(l[1].get<double>() >= min_layer_mm) || l[1].get<double>() > max_layer_mm)
        throw pipeline::bad_input(materials_json, where + ": bad layer " + l.dump() + ", expected [material, 0.1 <= mm <= 50]");
      const std::string mat = l[0];
      if (!j.contains("materials") || !j["materials"].contains(mat))
        throw pipeline::bad_input(materials_json, where + ": material '" + mat + "' not in \"materials\"");
      // a layer's groups are named <part>_<material>: a material twice in one stack left one
      // layer unnamed and a bone-less "<part>_bone_inner" surface, with exit 0
      for (const auto& [earlier, mm] : s)
        if (earlier == mat) throw pipeline::bad_input(materials_json, where + ": material '" + mat + "' twice in one stack");
      s.emplace_back(mat, l[1].get<double>());
    }
    return s;
  };
  const auto rigid = [&](const std::string& mat) {
    const auto& m = j["materials"][mat];
    return m.is_object() && m.contains("rigid") && m["rigid"].is_boolean() && m["rigid"].get<bool>();
  };
  std::map<std::string, Stack> out;
  if (kind == "head") {
    if (!j.contains("head_layers_mm")) throw pipeline::bad_input(materials_json, "no \"head_layers_mm\"");
    for (auto& [part, a] : j["head_layers_mm"].items()) {
      if (part[0] == '_') continue;
      const std::string where = "head_layers_mm." + part;
      // the back of the head is one rigid shell (the skull under little tissue); a stack there
      // made 22,913 wedges that no deck fixed
      if (part == "back_of_head")
        throw pipeline::bad_input(materials_json, where + ": the back of the head is a rigid shell and takes no stack");
      out[part] = parse_stack(a, where);
      // The face's tissue rests on bone: the decks fix the rigid innermost layer. Without one the
      // tissue floated; with a rigid layer above soft ones the bone lay on the skin.
      const Stack& stack = out[part];
      if (!rigid(stack.back().first))
        throw pipeline::bad_input(materials_json, where + ": the innermost layer, '" + stack.back().first +
                                                      "', is not rigid: a face part's tissue rests on bone");
      for (std::size_t i = 0; i + 1 < stack.size(); ++i)
        if (rigid(stack[i].first))
          throw pipeline::bad_input(materials_json, where + ": '" + stack[i].first +
                                                        "' is rigid but not the innermost layer (layers go from the skin inward)");
    }
  } else if (kind == "respirator") {
    if (!j.contains("respirator_layers_mm")) throw pipeline::bad_input(materials_json, "no \"respirator_layers_mm\"");
    out["respirator_inner"] = parse_stack(j["respirator_layers_mm"], "respirator_layers_mm");
  } else {
    throw pipeline::Error(pipeline::ErrorKind::usage, "kind '" + kind + "': expected head or respirator");
  }
  return out;
}

void require_cheeks_on_their_sides(const FeModel& surface, const std::string& surface_path) {
  const auto mean_x_mm = [&](const char* name) {
    const Block* b = surface.find(name);
    if (!b || b->conn.empty()) return std::nan("");
    double x_mm = 0;
    for (int node : b->conn) x_mm += surface.nodes[std::size_t(node)].x() / double(b->conn.size());
    return x_mm;
  };
  pipeline::require_cheeks_on_their_sides(surface_path, "group", mean_x_mm("left_cheek"), mean_x_mm("right_cheek"));
}

void require_one_oriented_sheet(const FeModel& surface, const std::string& surface_path) {
  std::map<std::pair<int, int>, int> directed;  // (from, to) → uses
  std::vector<int> parent(surface.nodes.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int a) {
    while (parent[std::size_t(a)] != a) a = parent[std::size_t(a)] = parent[std::size_t(parent[std::size_t(a)])];
    return a;
  };
  std::vector<char> used(surface.nodes.size(), 0);
  for (const Block& b : surface.blocks) {
    if (b.dim != 2 || b.nodes_per_elem != 3) continue;
    for (std::size_t e = 0; e < b.size(); ++e)
      for (int k = 0; k < 3; ++k) {
        const int from = b.conn[3 * e + std::size_t(k)], to = b.conn[3 * e + std::size_t((k + 1) % 3)];
        used[std::size_t(from)] = 1;
        parent[std::size_t(root(from))] = root(to);
        if (++directed[{from, to}] > 1)  // a flipped triangle, or a third on the edge
          throw pipeline::bad_input(surface_path, "the edge from " + position(surface, from) + " to " +
                                                      position(surface, to) +
                                                      " runs the same way in two triangles: a triangle flipped, or "
                                                      "more than two triangles on an edge");
      }
  }
  // (an edge in three triangles runs the same way in two of them: caught above)
  std::set<int> pieces;
  for (std::size_t i = 0; i < used.size(); ++i)
    if (used[i]) pieces.insert(root(int(i)));
  if (pieces.size() > 1)
    throw pipeline::bad_input(surface_path, "its triangles are in " + std::to_string(pieces.size()) +
                                                " separate pieces, expected one surface");
}

void require_clean_triangles(const FeModel& surface, const std::string& surface_path) {
  std::map<std::array<int, 3>, std::string> seen;  // sorted nodes → group
  for (const Block& b : surface.blocks) {
    if (b.dim != 2 || b.nodes_per_elem != 3) continue;
    for (std::size_t e = 0; e < b.size(); ++e) {
      std::array<int, 3> t = {b.conn[3 * e], b.conn[3 * e + 1], b.conn[3 * e + 2]};
      const auto which = [&] {
        const Eigen::Vector3d c = (surface.nodes[t[0]] + surface.nodes[t[1]] + surface.nodes[t[2]]) / 3;
        return b.name + "'s triangle " + std::to_string(e + 1) + " of " + std::to_string(b.size()) + ", at " +
               pipeline::format_position_mm(c.x(), c.y(), c.z()) + ",";
      };
      const Eigen::Vector3d &p = surface.nodes[t[0]], &q = surface.nodes[t[1]], &r = surface.nodes[t[2]];
      if (!((q - p).cross(r - p).norm() > 0)) throw pipeline::bad_input(surface_path, which() + " has zero area");
      std::sort(t.begin(), t.end());
      if (const auto [it, fresh] = seen.emplace(t, b.name); !fresh)
        throw pipeline::bad_input(surface_path, which() + " repeats a triangle of " + it->second);
    }
  }
}

void require_stack_for_every_part(const FeModel& surface, const std::map<std::string, Stack>& stacks,
                                  const std::string& surface_path, const std::string& materials_path) {
  for (const auto& [part, stack] : stacks) {
    const Block* b = surface.find(part);
    if (!b || b->dim != 2 || b->nodes_per_elem != 3) {
      // the other kind's surface: a respirator's without --kind respirator, or a head's with it
      const bool respirator_surface = surface.find("respirator_inner") != nullptr, respirator_stacks = stacks.count("respirator_inner");
      const std::string hint = respirator_surface && !respirator_stacks   ? "a respirator's surface: give --kind respirator"
                               : !respirator_surface && respirator_stacks ? "a head's surface: leave out --kind respirator"
                                                                          : "a renamed group, or not surface_mesh's output?";
      throw pipeline::bad_input(surface_path, "no triangle group " + part + ", which " + materials_path + " layers (" + hint + ")");
    }
  }
  for (const Block& b : surface.blocks)
    if (b.dim == 2 && b.nodes_per_elem == 3 && b.name != "back_of_head" && !stacks.count(b.name))
      throw pipeline::bad_input(materials_path, "no layer stack for part " + b.name + " of " + surface_path +
                                                    ": it would stay a bare surface");
}

std::map<std::string, int> parse_elements_per_tissue(const std::string& text, const std::map<std::string, Stack>& stacks) {
  std::map<std::string, int> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    const auto eq = item.find('=');
    const std::string name = item.substr(0, eq), count = eq == std::string::npos ? "" : item.substr(eq + 1);
    const bool integer = !count.empty() && count.size() <= 2 && std::all_of(count.begin(), count.end(), ::isdigit);
    const int n = integer ? std::stoi(count) : 0;
    if (name.empty() || n < 1 || n > 20)
      throw pipeline::Error(pipeline::ErrorKind::usage,
                            "--elements-per-tissue: '" + item + "', expected material=N with N an integer 1..20");
    bool used = false;
    for (const auto& [part, stack] : stacks)
      for (const auto& layer : stack) used = used || layer.first == name;
    if (!used)
      throw pipeline::Error(pipeline::ErrorKind::usage,
                            "--elements-per-tissue: '" + item + "': no layer of " + name + " in the stacks");
    if (!out.emplace(name, n).second)
      throw pipeline::Error(pipeline::ErrorKind::usage, "--elements-per-tissue: " + name + " given twice");
  }
  return out;
}

}  // namespace layering
