// Hole filling with fairing (CGAL triangulate_refine_and_fair_hole); the rule for the
// respirator rim is in fill_holes.h.
#include "scan2cad/fill_holes.h"

#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace PMP = CGAL::Polygon_mesh_processing;
using pipeline::SurfaceMesh;

namespace scan2cad {

namespace {

HoleInfo measure_loop(const SurfaceMesh& mesh, SurfaceMesh::Halfedge_index h) {
  HoleInfo info;
  std::vector<pipeline::Point> pts;
  for (auto e : CGAL::halfedges_around_face(h, mesh)) {
    ++info.boundary_edges;
    info.perimeter_mm += std::sqrt(CGAL::squared_distance(mesh.point(mesh.source(e)), mesh.point(mesh.target(e))));
    pts.push_back(mesh.point(mesh.target(e)));
  }
  double d2 = 0;  // O(n²) on one loop: loops are short except the respirator rim (≤ a few 1000)
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (std::size_t j = i + 1; j < pts.size(); ++j) d2 = std::max(d2, CGAL::squared_distance(pts[i], pts[j]));
  info.diameter_mm = std::sqrt(d2);
  return info;
}

// Fills a loop whose HoleInfo is measured already.
void fill_measured(SurfaceMesh& mesh, SurfaceMesh::Halfedge_index h, double fill_edge_mm, HoleInfo& info,
                   std::vector<pipeline::FaceIndex>& faces, std::vector<pipeline::VertexIndex>& verts) {
  // Liepa's refinement splits a triangle until its vertices are about (their mean edge) /
  // density apart; CGAL's default density is sqrt(2)
  const double mean_edge = info.perimeter_mm / double(std::max<std::size_t>(info.boundary_edges, 1));
  const double density = std::max(std::sqrt(2.0), mean_edge / fill_edge_mm);
  const auto res = PMP::triangulate_refine_and_fair_hole(
      mesh, h, std::back_inserter(faces), std::back_inserter(verts),
      CGAL::parameters::fairing_continuity(1).density_control_factor(density));
  info.faired = std::get<0>(res);
  info.faces_added = faces.size();
  info.filled = !faces.empty();
}

}  // namespace

HoleInfo fill_hole(SurfaceMesh& mesh, SurfaceMesh::Halfedge_index border, double fill_edge_mm,
                   std::vector<pipeline::FaceIndex>* faces, std::vector<pipeline::VertexIndex>* vertices) {
  HoleInfo info = measure_loop(mesh, border);
  std::vector<pipeline::FaceIndex> f;
  std::vector<pipeline::VertexIndex> v;
  fill_measured(mesh, border, fill_edge_mm, info, f, v);
  if (faces) *faces = std::move(f);
  if (vertices) *vertices = std::move(v);
  return info;
}

std::vector<HoleInfo> fill_holes(SurfaceMesh& mesh, ScanKind kind, std::vector<std::vector<pipeline::FaceIndex>>* fills,
                                 double fill_edge_mm) {
  std::vector<SurfaceMesh::Halfedge_index> loops;
  PMP::extract_boundary_cycles(mesh, std::back_inserter(loops));
  struct Loop {
    SurfaceMesh::Halfedge_index h;
    HoleInfo info;
  };
  std::vector<Loop> all;
  for (auto h : loops) all.push_back({h, measure_loop(mesh, h)});
  std::sort(all.begin(), all.end(), [](const Loop& a, const Loop& b) { return a.info.perimeter_mm > b.info.perimeter_mm; });
  // A rim goes round the nose and mouth: its perimeter exceeds the cup's largest extent (the
  // generated cups' rims are ~2.7 times it). A closed shell has no rim; a few open edges left in it
  // (the real Conforming cup's 4 mm gap) were kept open as its "rim" and reached surface_mesh as a
  // hole too small to mesh.
  const CGAL::Bbox_3 box = PMP::bbox(mesh);
  const double extent_mm = std::max({box.xmax() - box.xmin(), box.ymax() - box.ymin(), box.zmax() - box.zmin()});
  std::vector<HoleInfo> out;
  for (std::size_t i = 0; i < all.size(); ++i) {
    Loop& l = all[i];
    if (kind == ScanKind::respirator && i == 0 && l.info.perimeter_mm > extent_mm) {
      l.info.kept_open = true;
      out.push_back(l.info);
      continue;
    }
    std::vector<pipeline::FaceIndex> faces;
    std::vector<pipeline::VertexIndex> verts;
    fill_measured(mesh, l.h, fill_edge_mm, l.info, faces, verts);
    if (fills && l.info.filled) fills->push_back(std::move(faces));
    out.push_back(l.info);
  }
  return out;
}

}  // namespace scan2cad
