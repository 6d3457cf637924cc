#pragma once
/// Helpers of repair (internal): spikes, self-intersections, components (soup → mesh is
/// pipeline/soup_to_mesh.h).
#include <cstddef>

#include "pipeline/surface_mesh.h"

namespace scan2cad::internal {

/// Moves spike vertices onto their one-ring centroid; @return the number of moves.
/// A spike: distance from the vertex to the plane through the one-ring centroid with the
/// one-ring normal > factor × mean distance of the one-ring to its centroid. Border vertices are left alone.
std::size_t remove_spikes(pipeline::SurfaceMesh& mesh, double factor, int passes = 3);

/// Faces that intersect another face (PMP::self_intersections).
std::size_t count_self_intersecting_faces(const pipeline::SurfaceMesh& mesh);

/// What keep_largest_component found and removed.
struct ComponentsKept {
  std::size_t components = 0;     ///< connected components found (0 for an empty mesh)
  std::size_t faces_removed = 0;  ///< faces of the components removed
  double second_area_share = 0;   ///< the second largest component's area / the whole area, in [0, 0.5]
};

/// What remove_self_intersecting_faces found and deleted.
struct SelfIntersectionsCut {
  std::size_t crossing = 0;   ///< faces that intersected another face
  std::size_t faces_cut = 0;  ///< those and the faces around their vertices, deleted
  ComponentsKept pieces;      ///< the pieces the cut left; all but the largest were removed
};

/// Deletes every self-intersecting face and the faces around its vertices, splits the
/// non-manifold vertices this leaves and keeps the largest component. The cut can sever a thin
/// part (an ear's fin whose two sides crossed): `pieces` says what went with it, which the
/// caller must count and may refuse (a piece cut off is not a crossing face).
SelfIntersectionsCut remove_self_intersecting_faces(pipeline::SurfaceMesh& mesh);

/// Keeps the connected component of largest area, and measures the second largest's share of the
/// whole area (which tells a scan cut in two, or two objects, from debris). Area, not the face
/// count, says which piece is the object: debris may be finely triangulated.
ComponentsKept keep_largest_component(pipeline::SurfaceMesh& mesh);

}  // namespace scan2cad::internal
