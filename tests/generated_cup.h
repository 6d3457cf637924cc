// Test helpers: a generated respirator cup as a perfect reconstruction would give it, and which
// way a surface looks.
//
//   pipeline::SurfaceMesh clean_cup(const std::string& id)
//   double mean_normal_z(const pipeline::SurfaceMesh& mesh)
//
// clean_cup: the generator's closed thin shell (wall 1.5 mm) for the respirator `id` of
//   data/generator/respirators.json ("onesize", "twosize-s", ...), in its design frame (the
//   average face's: x lateral, y up, z out of the face), without scanner artifacts. Links
//   scan_generator.
// mean_normal_z: the area-weighted mean z of the face normals; < 0 where the surface looks toward
//   the face (-z), as a respirator's inner face does.
#pragma once

#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <string>
#include <vector>

#include "data/generator/head_model.h"
#include "data/generator/respirator_model.h"
#include "pipeline/surface_mesh.h"

inline pipeline::SurfaceMesh clean_cup(const std::string& id) {
  generator::HeadParams face;
  const auto p = generator::read_respirator_params(std::string(SOURCE_DIR) + "/data/generator/respirators.json", id, &face);
  const generator::Triangles t = generator::make_respirator(p, generator::HeadShape(face));
  std::vector<std::vector<std::size_t>> polygons;
  for (const auto& f : t.faces) polygons.push_back({f[0], f[1], f[2]});
  pipeline::SurfaceMesh mesh;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(t.points, polygons, mesh);
  return mesh;
}

inline double mean_normal_z(const pipeline::SurfaceMesh& mesh) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  double s = 0;
  for (auto f : mesh.faces()) s += PMP::compute_face_normal(f, mesh).z() * PMP::face_area(f, mesh);
  return s / PMP::area(mesh);
}
