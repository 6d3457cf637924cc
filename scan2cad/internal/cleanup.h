#pragma once
/// Helpers of repair (internal): soup → mesh, spikes, self-intersections.
#include <cstddef>

#include "pipeline/surface_mesh.h"

namespace scan2cad::internal {

struct SoupStats {
  std::size_t polygons_removed = 0, non_manifold_vertices_split = 0;
};

/// repair_polygon_soup + orient_polygon_soup + polygon_soup_to_polygon_mesh (CGAL); polygons
/// with more than 3 sides are triangulated. The soup is taken by value (CGAL edits it).
pipeline::SurfaceMesh soup_to_mesh(pipeline::PolygonSoup soup, SoupStats* stats);

/// Moves spike vertices onto their one-ring centroid; @return the number of moves.
/// A spike: distance from the vertex to the plane through the one-ring centroid with the
/// one-ring normal > factor × mean distance of the one-ring to its centroid. Border vertices are left alone.
std::size_t remove_spikes(pipeline::SurfaceMesh& mesh, double factor, int passes = 3);

/// Faces that intersect another face (PMP::self_intersections).
std::size_t count_self_intersecting_faces(const pipeline::SurfaceMesh& mesh);

/// Deletes every self-intersecting face, splits the non-manifold vertices this leaves and
/// keeps the largest component. @return the number of faces deleted.
std::size_t remove_self_intersecting_faces(pipeline::SurfaceMesh& mesh);

/// What keep_largest_component found and removed.
struct ComponentsKept {
  std::size_t components = 0;     ///< connected components found (0 for an empty mesh)
  std::size_t faces_removed = 0;  ///< faces of the components removed
  double second_area_share = 0;   ///< the second largest component's area / the whole area, in [0, 0.5]
};

/// Keeps the connected component of largest area, and measures the second largest's share of the
/// whole area (which tells a scan cut in two, or two objects, from debris). Area, not the face
/// count, says which piece is the object: debris may be finely triangulated.
ComponentsKept keep_largest_component(pipeline::SurfaceMesh& mesh);

}  // namespace scan2cad::internal
