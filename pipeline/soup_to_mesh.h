#pragma once
/// A polygon soup as read from a scan file → a triangle Surface_mesh (CGAL's soup repair).
#include <cstddef>

#include "pipeline/surface_mesh.h"

namespace pipeline {

/// What soup_to_mesh changed.
struct SoupStats {
  std::size_t polygons_removed = 0;             ///< degenerate and duplicate polygons
  std::size_t non_manifold_vertices_split = 0;  ///< points orient_polygon_soup duplicated
};

/// CGAL's repair_polygon_soup (duplicate points, degenerate and duplicate polygons),
/// orient_polygon_soup (non-manifold vertices are split), polygon_soup_to_polygon_mesh, then
/// triangulate_faces: the AABB trees, samplers and ray tests of the stages read three corners of
/// each face, and on a 10 mm square they missed points 4.95 mm inside it (sweep S).
///
/// @param[in]  soup   points [any unit] and polygons; taken by value (CGAL edits it)
/// @param[out] stats  what was changed (optional)
/// @return the mesh, possibly empty (the caller says what that means for its input)
/// @throws Error(bad_input) on "mesh" when a polygon cannot be triangulated
SurfaceMesh soup_to_mesh(PolygonSoup soup, SoupStats* stats = nullptr);

}  // namespace pipeline
