#pragma once
/// Hole filling with fairing (CGAL triangulate_refine_and_fair_hole).
///
/// Rule for which boundary loops are holes: on a head every loop is a hole (the output is
/// closed). On a respirator the loop with the longest perimeter is the rim the shell is meant
/// to have and stays open, if it is longer than the respirator's largest extent (a rim goes round
/// the nose and mouth; a closed shell has none); every other loop is a hole.
#include <cstddef>
#include <vector>

#include "pipeline/surface_mesh.h"
#include "scan2cad/scan_kind.h"

namespace scan2cad {

struct HoleInfo {
  std::size_t boundary_edges = 0;
  double perimeter_mm = 0;
  double diameter_mm = 0;  ///< largest distance between two of its boundary vertices [mm]
  bool kept_open = false;  ///< the respirator rim
  bool filled = false;     ///< triangulated and refined
  bool faired = false;     ///< fairing succeeded too (else only refined)
  std::size_t faces_added = 0;
};

/// Fills one boundary loop of `mesh` in place (CGAL triangulate_refine_and_fair_hole,
/// tangent-continuous fairing, refined at the scale `fill_edge_mm`: see fill_holes).
///
/// @param[in,out] mesh    triangle mesh [mm]
/// @param[in]     border  a border halfedge of the loop (its face is null)
/// @param[out]    faces, vertices  optional: the faces and the inner vertices the fill added
/// @return the loop's HoleInfo (kept_open false)
HoleInfo fill_hole(pipeline::SurfaceMesh& mesh, pipeline::SurfaceMesh::Halfedge_index border, double fill_edge_mm = 1.0,
                   std::vector<pipeline::FaceIndex>* faces = nullptr,
                   std::vector<pipeline::VertexIndex>* vertices = nullptr);

/// Fills the holes of `mesh` in place.
///
/// @param[in,out] mesh  triangle mesh [mm]; new faces are finer than their borders (fill_edge_mm)
/// @param[in]     kind  decides which loop stays open (see above)
/// @param[out]    fills optional: the faces each filled loop got, one list per filled loop
/// @param[in]     fill_edge_mm  the scale of the edges inside a fill [mm] (CGAL's refinement
///                      density is the loop's mean edge over it, at least CGAL's sqrt 2); default
///                      1. Liepa's refinement stops splitting a triangle once its centroid is
///                      within that scale of its vertices, so the inner edges come out about 1.7
///                      times it (1.70 at 1 mm, 1.68 at 0.7 mm on a sphere: fill_holes_test). Finer than the
///                      loop: a reconstructed head's loops have edges of ~3 mm where the surface
///                      is flat, and a fill at that size cannot take the shape of an eye socket
///                      when complete_by_symmetry reshapes it
/// @return one HoleInfo per boundary loop found, largest perimeter first
/// @note a loop CGAL cannot triangulate stays open and is reported with filled = false
std::vector<HoleInfo> fill_holes(pipeline::SurfaceMesh& mesh, ScanKind kind,
                                 std::vector<std::vector<pipeline::FaceIndex>>* fills = nullptr,
                                 double fill_edge_mm = 1.0);

}  // namespace scan2cad
