#include "solve/write_results.h"

#include <cstdio>
#include <set>
#include <string>

#include <gmsh.h>

#include "pipeline/error.h"
#include "pipeline/gmsh_session.h"
#include "pipeline/write_gmsh_model.h"

namespace solve {
namespace {
int gmsh_type(ElementType t) {
  switch (t) {
    case ElementType::tri3: return 2;
    case ElementType::quad4: return 3;
    case ElementType::tet4: return 4;
    case ElementType::hex8: return 5;
    case ElementType::wedge6: return 6;
  }
  return 0;
}
}  // namespace

void write_mesh_msh(const Model& m, const std::string& path, const std::function<void(const std::string&)>& append) {
  try {
    pipeline::GmshSession session;
    gmsh::model::add("results");
    std::vector<std::size_t> ntags(m.n_nodes());
    for (std::size_t i = 0; i < ntags.size(); ++i) ntags[i] = std::size_t(m.node_tag(i));
    std::size_t next_elem = 1;
    bool nodes_added = false;
    std::set<std::string> part_names;  // written as their elements: not again as surfaces or nodes
    for (const auto& p : m.parts) {
      part_names.insert(p.name);
      const int dim = is_membrane(p.type) ? 2 : 3;
      const int ent = gmsh::model::addDiscreteEntity(dim);
      if (!nodes_added) {
        gmsh::model::mesh::addNodes(dim, ent, ntags, m.X);
        nodes_added = true;
      }
      std::vector<std::size_t> etags(p.size()), conn(p.conn.size());
      for (auto& t : etags) t = next_elem++;
      for (std::size_t k = 0; k < conn.size(); ++k) conn[k] = ntags[p.conn[k]];
      gmsh::model::mesh::addElementsByType(ent, gmsh_type(p.type), etags, conn);
      const int pg = gmsh::model::addPhysicalGroup(dim, {ent});
      gmsh::model::setPhysicalName(dim, pg, p.name);
    }
    // Named surfaces (contact masters, faces of generated blocks) as triangle groups.
    for (const auto& [name, tris] : m.surfaces) {
      if (part_names.count(name) || tris.empty() || !nodes_added) continue;
      const int ent = gmsh::model::addDiscreteEntity(2);
      std::vector<std::size_t> etags(tris.size()), conn;
      for (auto& t : etags) t = next_elem++;
      for (const auto& t : tris)
        for (int id : t) conn.push_back(ntags[id]);
      gmsh::model::mesh::addElementsByType(ent, 2, etags, conn);
      const int pg = gmsh::model::addPhysicalGroup(2, {ent});
      gmsh::model::setPhysicalName(2, pg, name);
    }
    // The other node groups (the respirator's rim and the strap ends, lines and points in the
    // model) as points, so that results.msh names every group a deck can address: the nodes
    // whose force forces.csv tracks could not be picked in gmsh or ParaView.
    for (const auto& [name, nodes] : m.node_groups) {
      if (part_names.count(name) || m.surfaces.count(name) || nodes.empty() || !nodes_added) continue;
      const int ent = gmsh::model::addDiscreteEntity(0);
      std::vector<std::size_t> etags(nodes.size()), conn(nodes.size());
      for (std::size_t k = 0; k < nodes.size(); ++k) etags[k] = next_elem++, conn[k] = ntags[nodes[k]];
      gmsh::model::mesh::addElementsByType(ent, 15, etags, conn);  // 15: gmsh's one-node point
      const int pg = gmsh::model::addPhysicalGroup(0, {ent});
      gmsh::model::setPhysicalName(0, pg, name);
    }
    pipeline::write_gmsh_model(path, append);
  } catch (const std::string& e) {
    throw pipeline::io_failed(path, "gmsh cannot build the mesh: " + e);
  }
}

void append_node_data(std::ostream& out, const Model& m, const std::string& name, double time, int step,
                      const std::vector<double>& values, int ncomp) {
  const std::size_t n = m.n_nodes();
  out << "$NodeData\n1\n\"" << name << "\"\n1\n" << time << "\n3\n" << step << "\n" << ncomp << "\n" << n << "\n";
  char buf[64];
  for (std::size_t i = 0; i < n; ++i) {
    out << m.node_tag(i);
    for (int c = 0; c < ncomp; ++c) {
      std::snprintf(buf, sizeof buf, " %.9g", values[ncomp * i + c]);
      out << buf;
    }
    out << '\n';
  }
  out << "$EndNodeData\n";
}

int node_data_components(const std::string& field) { return field == "displacement" || field == "velocity" ? 3 : 1; }

double node_data_bytes_max(const Model& m) {
  double tag_chars = 0;  // the node tags as append_node_data writes them, one per line
  for (std::size_t i = 0; i < m.n_nodes(); ++i) tag_chars += double(std::to_string(m.node_tag(i)).size() + 1);
  double bytes = 0;
  for (const auto& f : m.output.node_data)
    bytes += 100 + double(f.size()) + tag_chars + 17.0 * node_data_components(f) * double(m.n_nodes());  // 100: header
  return bytes;
}

}  // namespace solve
