// Hole filling with fairing (CGAL triangulate_refine_and_fair_hole); the rule for the
// respirator rim is in fill_holes.h.
#include "scan2cad/fill_holes.h"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace PMP = CGAL::Polygon_mesh_processing;
using pipeline::SurfaceMesh;

namespace scan2cad {

std::vector<HoleInfo> fill_holes(SurfaceMesh& mesh, ScanKind kind, std::vector<std::vector<pipeline::FaceIndex>>* fills,
                                 double fill_edge_mm) {
  std::vector<SurfaceMesh::Halfedge_index> loops;
  PMP::extract_boundary_cycles(mesh, std::back_inserter(loops));
  struct Loop {
    SurfaceMesh::Halfedge_index h;
    HoleInfo info;
  };
  std::vector<Loop> all;
  for (auto h : loops) {
    Loop l{h, {}};
    std::vector<pipeline::Point> pts;
    for (auto e : CGAL::halfedges_around_face(h, mesh)) {
      ++l.info.boundary_edges;
      l.info.perimeter_mm += std::sqrt(CGAL::squared_distance(mesh.point(mesh.source(e)), mesh.point(mesh.target(e))));
      pts.push_back(mesh.point(mesh.target(e)));
    }
    double d2 = 0;  // O(n²) on one loop: loops are short except the respirator rim (≤ a few 1000)
    for (std::size_t i = 0; i < pts.size(); ++i)
      for (std::size_t j = i + 1; j < pts.size(); ++j) d2 = std::max(d2, CGAL::squared_distance(pts[i], pts[j]));
    l.info.diameter_mm = std::sqrt(d2);
    all.push_back(l);
  }
  std::sort(all.begin(), all.end(), [](const Loop& a, const Loop& b) { return a.info.perimeter_mm > b.info.perimeter_mm; });
  std::vector<HoleInfo> out;
  for (std::size_t i = 0; i < all.size(); ++i) {
    Loop& l = all[i];
    if (kind == ScanKind::respirator && i == 0) {
      l.info.kept_open = true;
      out.push_back(l.info);
      continue;
    }
    std::vector<pipeline::FaceIndex> faces;
    std::vector<pipeline::VertexIndex> verts;
    // Liepa's refinement splits a triangle until its vertices are about (their mean edge) /
    // density apart; CGAL's default density is sqrt(2)
    const double mean_edge = l.info.perimeter_mm / double(std::max<std::size_t>(l.info.boundary_edges, 1));
    const double density = std::max(std::sqrt(2.0), mean_edge / fill_edge_mm);
    const auto res = PMP::triangulate_refine_and_fair_hole(
        mesh, l.h, std::back_inserter(faces), std::back_inserter(verts),
        CGAL::parameters::fairing_continuity(1).density_control_factor(density));
    l.info.faired = std::get<0>(res);
    l.info.faces_added = faces.size();
    l.info.filled = !faces.empty();
    if (fills && l.info.filled) fills->push_back(std::move(faces));
    out.push_back(l.info);
  }
  return out;
}

}  // namespace scan2cad
