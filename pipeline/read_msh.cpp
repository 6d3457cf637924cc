// read_msh: see read_msh.h.
#include "pipeline/read_msh.h"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "pipeline/error.h"
#include "pipeline/gmsh_session.h"
#include "pipeline/require_file.h"

namespace pipeline {
namespace {

MshFile read_open_model(const std::string& path) {
  MshFile f;
  std::vector<std::size_t> tags;
  std::vector<double> xyz, param;
  gmsh::model::mesh::getNodes(tags, xyz, param, -1, -1, false, false);
  if (tags.empty()) throw bad_input(path, "no nodes (empty, or not a gmsh mesh)");
  // Tag → where gmsh lists it first (a node on an entity's boundary may be listed once per
  // entity), then → its index in f once it is stored there.
  std::map<std::size_t, std::size_t> index;
  for (std::size_t i = 0; i < tags.size(); ++i) index.emplace(tags[i], i);
  // The nodes in tag order, not gmsh's: gmsh lists them entity by entity, and createTopology
  // numbers the curve and point entities of surface_mesh's output in pointer order, so the same
  // surface read from another path listed its nodes in another order and layers wrote a
  // permuted model. Tags are the writer's and do not move.
  for (auto& [tag, i] : index) {
    // Checked here because a NaN node slips through every later geometric test (comparisons
    // with NaN are false) and surfaces as thinning failures or a floating-point trap.
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(xyz[3 * i + k]))
        throw bad_input(path, "node " + std::to_string(tag) + " has a non-finite coordinate");
    f.xyz.insert(f.xyz.end(), xyz.begin() + 3 * long(i), xyz.begin() + 3 * long(i) + 3);
    i = f.node_tags.size();
    f.node_tags.push_back(tag);
  }
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups);
  for (const auto& [dim, tag] : groups) {
    MshGroup g;
    g.dim = dim;
    g.tag = tag;
    gmsh::model::getPhysicalName(dim, tag, g.name);
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
    for (int entity : entities) {
      std::vector<int> types;
      std::vector<std::vector<std::size_t>> element_tags, element_nodes;
      gmsh::model::mesh::getElements(types, element_tags, element_nodes, dim, entity);
      for (std::size_t t = 0; t < types.size(); ++t) {
        MshElements block;
        block.gmsh_type = types[t];
        std::string type_name;
        int type_dim, order, primary_nodes;
        std::vector<double> local_coords;
        gmsh::model::mesh::getElementProperties(types[t], type_name, type_dim, order, block.nodes_per_element,
                                                local_coords, primary_nodes);
        block.conn.reserve(element_nodes[t].size());
        for (std::size_t n : element_nodes[t]) {
          const auto it = index.find(n);
          if (it == index.end())
            throw bad_input(path, "an element of group " + (g.name.empty() ? std::to_string(tag) : g.name) +
                                      " uses missing node " + std::to_string(n));
          block.conn.push_back(int(it->second));
        }
        g.elements.push_back(std::move(block));
      }
    }
    f.groups.push_back(std::move(g));
  }
  return f;
}

// gmsh reads a file whose $Nodes section lost its $EndNodes without a word and skips to the
// end, so the elements vanish and a stage wrote an empty model with exit 0. In an ASCII file
// every section must close before the next opens; a binary file's sections hold raw bytes after
// $MeshFormat, so only that one is looked at there.
void check_sections_closed(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line, open_section;
  std::size_t line_no = 0, open_line = 0;
  bool binary = false, format_seen = false;
  while (!binary && std::getline(in, line)) {
    ++line_no;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
    if (line_no == 1 && line != "$MeshFormat") return;  // not a gmsh 2/4 file: gmsh's own reader decides
    if (open_section == "MeshFormat" && !format_seen && !line.empty() && line[0] != '$') {
      std::istringstream words(line);
      double version = 0;
      int file_type = 0;
      words >> version >> file_type;
      binary = file_type == 1;
      format_seen = true;
      continue;
    }
    if (line.empty() || line[0] != '$') continue;
    const std::string name = line.substr(1);
    if (open_section.empty()) {
      if (name.rfind("End", 0) == 0)
        throw bad_input(path, "line " + std::to_string(line_no) + ": " + line + " closes no open section");
      open_section = name, open_line = line_no;
    } else if (name == "End" + open_section) {
      open_section.clear();
    } else if (open_section != "Comments") {
      throw bad_input(path, "section $" + open_section + " (line " + std::to_string(open_line) +
                                ") is not closed by $End" + open_section + " before line " + std::to_string(line_no) +
                                " (" + line + ")");
    }
  }
  if (!binary && !open_section.empty())
    throw bad_input(path, "section $" + open_section + " (line " + std::to_string(open_line) +
                              ") is not closed by $End" + open_section + " (truncated file?)");
}

}  // namespace

MshFile read_msh(const std::string& path) {
  require_file(path);
  GmshSession session;
  try {
    gmsh::open(path);
    check_sections_closed(path);
    return read_open_model(path);
  } catch (const std::string& e) {  // the gmsh API throws its last error message as a string
    throw bad_input(path, "gmsh cannot read it: " + e);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw bad_input(path, std::string("gmsh cannot read it: ") + e.what());
  }
}

}  // namespace pipeline
