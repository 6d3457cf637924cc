// pipeline::soup_to_mesh (soup_to_mesh.h).
#include "pipeline/soup_to_mesh.h"

#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>

#include "pipeline/error.h"

namespace pipeline {

SurfaceMesh soup_to_mesh(PolygonSoup soup, SoupStats* stats) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  const std::size_t polys0 = soup.polygons.size();
  PMP::repair_polygon_soup(soup.points, soup.polygons);
  const std::size_t points0 = soup.points.size();
  PMP::orient_polygon_soup(soup.points, soup.polygons);  // duplicates points at non-manifold vertices
  SurfaceMesh mesh;
  PMP::polygon_soup_to_polygon_mesh(soup.points, soup.polygons, mesh);
  if (!PMP::triangulate_faces(mesh))
    throw bad_input("mesh", "a polygon that cannot be cut into triangles (self-crossing or folded?)");
  if (stats) {
    stats->polygons_removed = polys0 - soup.polygons.size();
    stats->non_manifold_vertices_split = soup.points.size() - points0;
  }
  return mesh;
}

}  // namespace pipeline
