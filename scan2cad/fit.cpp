#include "scan2cad/fit.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>

#include "pipeline/error.h"

namespace scan2cad {

using pipeline::SurfaceMesh;

namespace {

const char* head_names[] = {"back_of_head", "forehead", "left_cheek", "right_cheek", "chin"};

}  // namespace

std::vector<FitPart> fit_surfaces(const SurfaceMesh& mesh, const std::string& kind) {
  auto found = mesh.property_map<pipeline::FaceIndex, int>(pipeline::part_property);
  if (!found.second) throw pipeline::bad_input("fit", "no face property \"part\" (run segment first)");
  const auto label = found.first;
  // 1. Parts present, with their names.
  std::map<int, std::vector<pipeline::FaceIndex>> faces;
  for (auto f : mesh.faces()) {
    const int l = label[f];
    if (kind == "head" ? (l < 0 || l > 4) : l != 0)
      throw pipeline::bad_input("fit", "face " + std::to_string(std::size_t(f)) + " has part " +
                                           std::to_string(l) + ", not a " + kind + " part label");
    if (mesh.degree(f) != 3) throw pipeline::bad_input("fit", "face " + std::to_string(std::size_t(f)) + " is not a triangle");
    faces[l].push_back(f);
  }
  std::vector<FitPart> parts;
  for (auto& [l, fs] : faces)
    parts.push_back({kind == "head" ? head_names[l] : "respirator_inner", l, l + 1});

  // 2. One discrete surface per part; a node belongs to the first part that uses it (gmsh
  //    re-classifies the boundary nodes onto the curves in createTopology).
  gmsh::model::add("fitted");
  std::vector<int> owner(mesh.number_of_vertices(), 0);
  for (auto& p : parts) gmsh::model::addDiscreteEntity(2, p.surface_tag);
  for (auto& p : parts) {
    std::vector<std::size_t> node_tags;
    std::vector<double> coords;
    std::vector<std::size_t> tri;
    for (auto f : faces[p.label])
      for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
        tri.push_back(std::size_t(v) + 1);
        if (!owner[v]) {
          owner[v] = p.surface_tag;
          node_tags.push_back(std::size_t(v) + 1);
          const auto& q = mesh.point(v);
          coords.insert(coords.end(), {q.x(), q.y(), q.z()});
        }
      }
    gmsh::model::mesh::addNodes(2, p.surface_tag, node_tags, coords);
    std::vector<std::size_t> elem_tags(tri.size() / 3);
    for (std::size_t i = 0; i < elem_tags.size(); ++i) elem_tags[i] = 0;
    gmsh::model::mesh::addElementsByType(p.surface_tag, 2, {}, tri);
  }
  // 3. Boundary curves and corner points from the mesh, then the parametrizations.
  gmsh::model::mesh::createTopology(true, true);
  try {
    gmsh::model::mesh::createGeometry();
  } catch (...) {
    throw pipeline::algorithm_failed("fit", "gmsh cannot parametrize the parts (each must be a disk)");
  }
  for (auto& p : parts) {
    gmsh::model::addPhysicalGroup(2, {p.surface_tag}, p.surface_tag);
    gmsh::model::setPhysicalName(2, p.surface_tag, p.name);
  }
  return parts;
}

std::vector<FitDeviation> fit_deviation(const SurfaceMesh& reference, const std::vector<FitPart>& parts,
                                        double check_size_mm) {
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel, Primitive>>;
  Tree tree(faces(reference).first, faces(reference).second, reference);
  tree.accelerate_distance_queries();

  gmsh::option::setNumber("Mesh.MeshSizeMin", check_size_mm);
  gmsh::option::setNumber("Mesh.MeshSizeMax", check_size_mm);
  if (const char* a = std::getenv("FIT_ALGO")) gmsh::option::setNumber("Mesh.Algorithm", std::atof(a));
  try {
    gmsh::model::mesh::clear();
    gmsh::model::mesh::generate(2);
  } catch (...) {
    throw pipeline::algorithm_failed("fit", "gmsh cannot mesh the fitted geometry at " +
                                                std::to_string(check_size_mm) + " mm");
  }
  std::vector<FitDeviation> out;
  for (const auto& p : parts) {
    FitDeviation d;
    d.name = p.name;
    std::vector<std::size_t> tags;
    std::vector<double> xyz, uv;
    gmsh::model::mesh::getNodes(tags, xyz, uv, 2, p.surface_tag, true, false);
    std::map<std::size_t, std::array<double, 3>> node;
    double sum2 = 0;
    for (std::size_t i = 0; i < tags.size(); ++i) {
      const pipeline::Point q(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
      node[tags[i]] = {q.x(), q.y(), q.z()};
      const double dist = std::sqrt(tree.squared_distance(q));
      sum2 += dist * dist;
      d.max_mm = std::max(d.max_mm, dist);
    }
    d.samples = tags.size();
    d.rms_mm = tags.empty() ? 0 : std::sqrt(sum2 / tags.size());
    std::vector<std::size_t> etags, enodes;
    gmsh::model::mesh::getElementsByType(2, etags, enodes, p.surface_tag);
    double csum2 = 0;
    for (std::size_t e = 0; e < etags.size(); ++e) {
      double c[3] = {0, 0, 0};
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) c[j] += node[enodes[3 * e + k]][j] / 3.0;
      const double dist = std::sqrt(tree.squared_distance(pipeline::Point(c[0], c[1], c[2])));
      csum2 += dist * dist;
      d.chord_max_mm = std::max(d.chord_max_mm, dist);
    }
    d.chord_rms_mm = etags.empty() ? 0 : std::sqrt(csum2 / etags.size());
    out.push_back(d);
  }
  return out;
}

}  // namespace scan2cad
