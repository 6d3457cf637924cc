#pragma once
/// Repair of a reconstructed or scanned surface into a clean, manifold triangle mesh.
///
/// Steps, in order (each counted in RepairReport):
///  0. the faces on a table or turntable the object stood on (remove_support_plane.h; a
///     scanner's own mesh may hold it) are removed;
///  1. soup → mesh: CGAL repair_polygon_soup (duplicate points, degenerate and duplicate
///     polygons), orient_polygon_soup (non-manifold vertices are split),
///     polygon_soup_to_polygon_mesh; then remove_degenerate_faces;
///  2. small disconnected components are removed (the largest one is kept); a second piece of
///     more than max_second_component_share of the area is bad input (a scan cut in two, two
///     objects), not debris;
///  3. spikes: a vertex farther from the plane of its one-ring than `spike_factor` × the mean
///     radius is moved onto the one-ring centroid (no library does this; see cleanup.cpp);
///  4. self-intersecting faces are deleted with the faces around their vertices (their holes are
///     filled in step 5); a piece the cut severs is removed and counted as in step 2, and refused
///     as in step 2 when it holds more than max_second_component_share of the area;
///  5. holes are filled with triangulate_refine_and_fair_hole (see fill_holes.h for which
///     boundary loops stay open: none on a head, the largest — the rim — on a respirator);
///     on a head the fills are then reshaped after the mirrored scanned surface where the head
///     is symmetric (complete_by_symmetry.h);
///  6. the surface is relaxed: `smoothing_iterations` steps of mean-curvature flow
///     (PMP::smooth_shape, border vertices held; a flow that moves a vertex more than
///     max_smoothing_move_mm, or leaves under 70 % of the area, is an error) and then isotropic
///     remeshing to `target_edge_mm` (tangential relaxation included); a respirator's rim is
///     split to the target length and kept in place;
///  7. any self-intersection the remeshing created is cut out and filled again (≤ 3 rounds).
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/surface_mesh.h"
#include "scan2cad/complete_by_symmetry.h"
#include "scan2cad/fill_holes.h"
#include "scan2cad/scan_kind.h"

namespace scan2cad {

/// The most triangles the remeshing may make: ~60 times a head at the default 1.5 mm edge
/// (NIOSH medium, 167,890 mm²: ~170,000), several GB and minutes of remeshing.
constexpr double max_remeshed_triangles = 1e7;

/// The remeshing's edge is at most the object's largest extent over this (a head 11 mm, a
/// respirator 5 mm; the default is 1.5).
constexpr double min_edges_across = 25;

/// The largest area share a removed component may have: scanner debris is well under 1 %; a
/// head cut in two by a 4 mm gap across the face had 36 % in its second piece, two heads 50 %.
constexpr double max_second_component_share = 0.1;

/// The farthest the smoothing of step 6 may move a vertex [mm]: relaxing a scan's noise moves
/// vertices by tenths of a mm, a flow that moves one farther reshapes the object.
constexpr double max_smoothing_move_mm = 2.0;

struct RepairOptions {
  /// target edge length of the isotropic remeshing [mm]; default 1.5, 0 = no remeshing; an edge
  /// that would give more than max_remeshed_triangles on the input's area, or longer than the
  /// input's largest extent / min_edges_across, is a usage error
  double target_edge_mm = 1.5;
  /// remeshing iterations; default 3, range 1–20
  int remesh_iterations = 3;
  /// mean-curvature-flow steps (PMP::smooth_shape); default 1, 0 = none
  int smoothing_iterations = 1;
  /// time step of smooth_shape (CGAL's unit); default 1e-4, range > 0
  double smoothing_time = 1e-4;
  /// spike threshold: distance to the one-ring plane / mean one-ring radius (1: sides steeper
  /// than 45 deg, 2: steeper than 63 deg). Default 2: at 1 it moved one vertex of each NIOSH
  /// head's acceptance scan, on real features (NIOSH large's ear fin, ~1.5 mm across and 3 mm
  /// tall, came out 1.46 mm off instead of under 1.3; NIOSH medium's neck lip 3.94 mm instead of
  /// 3.91), none at 2, and the generated heads give the same figures at 1, 2 and 100; a spike
  /// that an outlier leaves is steeper (5 mm on 2.6 mm edges: ~3.8; the remove_spikes test)
  double spike_factor = 2.0;
  /// heads: reshape the hole fills after the mirror image of the scanned other side; default on
  bool symmetric_completion = true;
  /// the faces on a table or turntable the object stood on (remove_support_plane.h), which a
  /// scanner's own meshing may export with the object, are removed first; false keeps them
  bool remove_support = true;
  SymmetricCompletionOptions symmetry;
  /// [mm], 0 = no check: the largest piece may span at most this (the CLI: 1.6 of the kind's
  /// size when it detected the unit, pipeline::largest_real_share_of_extent): a head given as a
  /// respirator went on to align and segment
  double max_extent_mm = 0;
};

/// What repair changed, as written to the JSON report.
struct RepairReport {
  std::size_t input_vertices = 0, input_faces = 0;
  std::size_t support_faces_removed = 0;      ///< on a table or turntable (RepairOptions::remove_support)
  std::size_t soup_polygons_removed = 0;      ///< by repair_polygon_soup (duplicates, degenerate)
  std::size_t non_manifold_vertices_split = 0;  ///< by orient_polygon_soup
  std::size_t degenerate_faces_removed = 0;
  std::size_t components_removed = 0, component_faces_removed = 0;
  std::size_t spike_vertices_moved = 0;
  std::size_t self_intersecting_faces_before = 0, self_intersecting_faces_removed = 0;
  std::vector<HoleInfo> holes;                ///< every boundary loop met, filled or kept open
  bool symmetric_completion_run = false;      ///< step 5's completion was tried (heads only)
  SymmetricCompletionReport symmetry;         ///< its result, one entry per filled hole of step 5
  int smoothing_iterations = 0;      ///< steps done (0 when CGAL's solve failed and nothing moved)
  double smoothing_max_move_mm = 0;  ///< the farthest a vertex moved in them
  double target_edge_mm = 0, mean_edge_mm = 0;
  std::size_t output_vertices = 0, output_faces = 0;
  std::size_t boundary_loops_after = 0;
  bool closed = false, manifold = false, self_intersecting_after = false;
  double area_mm2 = 0, volume_mm3 = 0;  ///< volume only when closed

  nlohmann::json to_json() const;
  /// A few lines for stderr.
  std::string summary() const;
  /// "" or, when a hole at least `min_diameter_mm` across was filled, a warning naming it: that
  /// part of the surface is a faired patch, not the scan. A face-only scan's back of the head
  /// (243 mm across) came out 178 mm deep where the head is 239, and the straps laid over it
  /// were stretched half as much, with nothing to say so (sweep O). Default 150 mm: over a neck
  /// opening (~120 mm), under the back of a face-only scan or a missing crown (~170 mm).
  std::string large_fill_warning(double min_diameter_mm = 150.0) const;
};

/// Repairs a polygon soup into a clean surface.
///
/// @param[in]  soup    #P points [mm] and polygons (any orientation, may be non-manifold)
/// @param[in]  kind    head (closed output) or respirator (rim kept open)
/// @param[in]  opt     RepairOptions
/// @param[out] report  what was changed (optional)
/// @return a manifold triangle mesh [mm], outward-oriented when closed
/// @throws pipeline::Error(bad_input) when the soup has no usable faces or is in two large pieces;
///         Error(algorithm) when a head cannot be closed, a respirator keeps a hole beside its
///         rim, the smoothing reshapes the object, or self-intersections or non-manifold
///         vertices remain.
pipeline::SurfaceMesh repair(const pipeline::PolygonSoup& soup, ScanKind kind, const RepairOptions& opt,
                             RepairReport* report = nullptr);

}  // namespace scan2cad
