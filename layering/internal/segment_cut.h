#pragma once
/// Cutting a triangle mesh along the zero level set of a per-vertex scalar field.
/// Written by hand because CGAL 5.5 has no refine_mesh_at_isolevel (added in CGAL 5.6) and
/// PMP::clip only cuts along planes.
#include <vector>

#include "pipeline/surface_mesh.h"

namespace layering::internal {

using Field = pipeline::SurfaceMesh::Property_map<pipeline::VertexIndex, double>;

/// Refines `mesh` so that no triangle has vertex values of `fields[cut]` of both signs: every
/// edge whose end values have strictly opposite signs is split at the linearly interpolated zero
/// and the crossed triangles are re-triangulated. All `fields` are interpolated linearly onto the
/// new vertices. Values with |f| < snap are first set to 0 (no slivers thinner than `snap`).
///
/// @param[in,out] mesh    triangle mesh (closed or with borders)
/// @param[in,out] fields  per-vertex fields of `mesh` [any unit, the same as snap]
/// @param[in]     cut     index of the field to cut along
/// @param[in]     snap    snapping tolerance, same unit as the field (≥ 0)
/// @post the mesh is still a triangle mesh; existing vertices keep their positions
void cut_at_zero(pipeline::SurfaceMesh& mesh, std::vector<Field>& fields, std::size_t cut, double snap);

}  // namespace layering::internal
