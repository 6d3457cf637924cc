#pragma once
/// Smooth-surface (CAD) step of the paper. Each labelled part of a segmented surface is remeshed
/// isotropically (CGAL PMP::isotropic_remeshing, part boundaries kept as constrained polylines,
/// new vertices projected back onto the input), which removes the slivers the level-set cuts of
/// `segment` leave, and becomes a discrete gmsh surface with its boundary curves (shared between
/// neighbouring parts) and a named 2D physical group.
///
/// Why not gmsh's own re-meshing of parametrized discrete surfaces: gmsh 4.8 maps each part
/// harmonically onto a disk; the back of the head (the whole head minus the face) is far from a
/// disk, its parametrization is crushed near the boundary and meshing fails ("Unable to recover the
/// edge", intersecting 1D mesh in parameter space) at every algorithm, with or without slivers.
/// The remeshed triangles ARE the fitted surface (they interpolate the input), so the deviation is
/// measured directly between this surface and the input (fit_deviation).
#include <string>
#include <vector>

#include "pipeline/surface_mesh.h"

namespace scan2cad {

/// One part as a gmsh surface.
struct FitPart {
  std::string name;     ///< physical group name (forehead, ..., or respirator_inner)
  int label = 0;        ///< "f:part" value
  int surface_tag = 0;  ///< gmsh surface tag (= physical group tag = label + 1)
};

/// Checks the part labels of a segmented mesh.
/// @param[in] kind "head" (labels 0..4: back_of_head, forehead, left_cheek, right_cheek, chin) or
///                 "respirator" (one part, label 0, named respirator_inner)
/// @throws pipeline::Error(bad_input) if "f:part" is missing or not an int, a label is unknown
///         for `kind`, a face is not a triangle, a head lacks a part or has one in separate pieces,
///         or a head's left cheek lies at mean x <= 0 or its right one at x >= 0 (align's frame)
void check_parts(const pipeline::SurfaceMesh& segmented, const std::string& kind);

/// Isotropic remeshing of a part-labelled triangle mesh [mm]:
/// PMP::isotropic_remeshing to `edge_mm` on every part (3 iterations; more move the relaxed
/// cuts further off the input), then (if `back_edge_mm` > 0) to `back_edge_mm` on the
/// back_of_head part only (label 0, head meshes) and the face parts once more.
/// The worst triangles are not improved here (see improve_triangles, used by surface_mesh):
/// its smoothing would move the fitted surface off the input. Part boundaries and open
/// borders are constrained (their edges are split/collapsed along the cut, never moved off it);
/// every new face keeps its "f:part".
/// @throws pipeline::Error(bad_input) as check_parts
pipeline::SurfaceMesh remesh_parts(const pipeline::SurfaceMesh& segmented, const std::string& kind,
                                   double edge_mm, double back_edge_mm = 0);

/// Marks the corners of the open borders of `mesh`: vertices where the border turns by at least
/// `min_turn_deg` (remesh_parts keeps them fixed so that the rim's shape is not cut off). A jog,
/// corners within `jog_mm` of each other along the border whose signed turns add up to less than
/// `min_turn_deg` (a small step, noise), is not marked. Every border vertex's flag is set.
/// @return the number of border vertices left unmarked as parts of jogs
std::size_t mark_border_corners(const pipeline::SurfaceMesh& mesh, double min_turn_deg, double jog_mm,
                                pipeline::SurfaceMesh::Property_map<pipeline::VertexIndex, bool> corner);

/// The most triangles `fit --edge` may ask for (pipeline::require_affordable_edge): ~10 times a
/// head at the default 2 mm (~100,000 with the refined places); --edge 0.3 on a head (~4 million)
/// ran for minutes past 1 GB.
constexpr double max_fitted_triangles = 1e6;

/// fit warns where a part of its output is farther than this from the input [mm]: the chain's fits
/// stay within 0.9 mm at the 2 mm default edge.
inline constexpr double fit_deviation_warning_mm = 1.0;

/// The fit stage. Heads: constrained isotropic remeshing at `edge_mm` as remesh_parts, with the
/// sharp edges (> 60 deg) kept as constraints too; then, where that uniform surface misses the
/// input by more than `refine_above_mm` (highly curved places such as the ears: 1.2-1.5 mm at
/// 2 mm edges on the generated heads), the input is remeshed again with those places (grown by
/// ~2 edges) at edge_mm / 2 and the rest at edge_mm. Returns the uniform surface if nothing
/// misses by more (or refine_above_mm <= 0). Respirators: remesh_parts (its rim handling).
/// @param[out] refined_faces if given: input faces in the refined region (0 if none)
/// @throws pipeline::Error(bad_input) as check_parts
pipeline::SurfaceMesh fit_parts(const pipeline::SurfaceMesh& segmented, const std::string& kind, double edge_mm,
                                double refine_above_mm = 0.5, std::size_t* refined_faces = nullptr);

/// Removes slivers that sit on a cut (a border or part-boundary edge): for every triangle with
/// gamma < `below_gamma` that has a cut edge, its vertex opposite that edge, if it lies on no cut
/// itself (an interior vertex of one part, e.g. almost on a straight rim edge between two rim
/// vertices), is collapsed into the nearer end of the cut edge (else the other end), if CGAL's
/// link condition holds, the worst triangle around the vertex gets better and no remaining
/// triangle turns by more than 20 deg. Cut vertices never move, so borders and part boundaries
/// keep their vertices and shape; faces keep their "f:part". Then every flat ear on the border
/// (a border vertex with one triangle, gamma < `below_gamma`, lying within 2 % of the base
/// length from the segment between its two neighbours and between them) loses its triangle:
/// the base becomes the border. Garbage is collected.
/// @return the number of vertices removed (collapsed or ear tips)
std::size_t collapse_slivers_at_cuts(pipeline::SurfaceMesh& mesh, double below_gamma);

/// Raises the worst triangles of a remeshed, part-labelled mesh: first collapse_slivers_at_cuts
/// (gamma < 0.3), then rounds of quality-driven edge flips inside each part (an edge is flipped when that raises the smaller gamma of its two
/// triangles and the two are within 20 deg of coplanar) followed by CGAL angle smoothing of the
/// free vertices (PMP::angle_and_area_smoothing, angle term only, moves projected back onto the
/// surface as it was). Part cuts and borders are neither flipped nor moved.
/// @return the number of edges flipped
std::size_t improve_triangles(pipeline::SurfaceMesh& mesh, int rounds = 3);

/// gmsh's triangle quality "gamma" = 2 r / R (inscribed over circumscribed radius; 1 for an
/// equilateral triangle, 0 for a degenerate one).
double triangle_gamma(const pipeline::Point& a, const pipeline::Point& b, const pipeline::Point& c);

/// The smallest triangle_gamma over the faces of a triangle mesh (1 if it has none).
double min_triangle_gamma(const pipeline::SurfaceMesh& mesh);

/// Builds the part-wise model in the CURRENT gmsh model (gmsh must be initialized; a model
/// named "fitted" is added): one discrete surface and one named 2D physical group per part, nodes
/// shared (one global numbering = vertex index + 1), boundary curves and corner points created
/// by gmsh (createTopology) and then numbered and directed by node tags
/// (internal::number_topology_by_node_tags), so the model does not depend on the heap layout. If
/// `parametrize`, gmsh instead computes each part's parametrization (createGeometry), needed only
/// to re-mesh the model inside gmsh; the numbering is then gmsh's.
/// @return the parts, in label order
/// @throws pipeline::Error(bad_input) as check_parts; Error(algorithm) if gmsh fails
std::vector<FitPart> build_part_model(const pipeline::SurfaceMesh& mesh, const std::string& kind,
                                      bool parametrize);

/// Deviation of a fitted surface from the reference (repaired/segmented) mesh, per part.
struct FitDeviation {
  std::string name;
  std::size_t samples = 0;            ///< points measured in both directions
  double rms_mm = 0, max_mm = 0;      ///< both directions pooled [mm]
  pipeline::Point max_at{0, 0, 0};    ///< the sample point where max_mm was measured
  /// the same samples' largest distance to the other surface's SAME part [mm]: max_mm plus how
  /// far the part's outline moved. A fitted outline edge is a chord of the reference's cut
  /// polyline, so near a sharp bend of the cut it lies over the neighbouring part by up to about
  /// one fitted edge while the surface itself stays close (generated large head, 2 mm edges:
  /// 1.26 mm here where max_mm is 0.34 mm, at the cheek/forehead cut beside the eye)
  double outline_shift_mm = 0;
  pipeline::Point outline_shift_at{0, 0, 0};
};

/// Per part: distances of the fitted part's samples (each triangle's first corner and its
/// centroid) to the whole reference surface, and of the reference part's samples to the whole
/// fitted surface (AABB trees); outline_shift_mm measures the same samples against the other surface's
/// same part.
std::vector<FitDeviation> fit_deviation(const pipeline::SurfaceMesh& reference,
                                        const pipeline::SurfaceMesh& fitted, const std::string& kind);

/// Part name for a label and kind.
std::string fit_part_name(int label, const std::string& kind);

}  // namespace scan2cad
