#pragma once
/// Layered pentahedron (6-node wedge) models of the face parts and of the respirator, and the
/// finite-element model container every meshing stage shares (read from / written to gmsh .msh).
///
/// How layers are built (see layering/README.md for the full rationale):
///  * one inward offset direction per skin node, from area-weighted vertex normals smoothed over
///    the whole face (ALL parts together), so neighbouring parts share skin nodes AND columns;
///  * one common depth partition for all parts: the union of every part's tissue interfaces and
///    sub-layer levels; a part's wedges run down the shared columns to its own total depth. So
///    parts with different stacks meet conformingly (no gap, overlap or hanging node); across a
///    part boundary a thin stack (forehead, 7 mm) simply ends where the thicker one continues;
///  * concave / thin places are detected (ray cast through the head with a CGAL AABB tree,
///    per-wedge volume and scaled Jacobian, CGAL triangle-soup self-intersection of all element
///    faces) and fixed by locally scaling the column depth down; every reduction is reported.
#include <Eigen/Core>

#include <map>
#include <string>
#include <vector>

namespace layering {

/// One physical group = one block of elements of one type. Node ids are 0-based into FeModel::nodes.
struct Block {
  std::string name;        ///< physical group name (e.g. "left_cheek_fat", "head_skin")
  int dim = 2;             ///< 0 points, 1 lines, 2 surfaces, 3 volumes
  int nodes_per_elem = 3;  ///< 1 point, 2 line, 3 triangle, 4 quadrangle, 6 wedge
  std::vector<int> conn;   ///< #elements × nodes_per_elem
  std::size_t size() const { return conn.size() / nodes_per_elem; }
};

/// A finite-element model: nodes [mm] and named blocks (gmsh physical groups).
struct FeModel {
  std::vector<Eigen::Vector3d> nodes;
  std::vector<Block> blocks;
  const Block* find(const std::string& name) const;  ///< nullptr if absent
};

/// Reads every physical group of a gmsh .msh (2.x or 4.x, ASCII or binary; MSH 1 refused) with the gmsh API.
/// @throws pipeline::Error(bad_input) naming the file if it is missing, unreadable or has no group.
FeModel read_fe_model(const std::string& path);

/// Writes a gmsh .msh 4.1 (ASCII) atomically: one discrete entity and one named physical group per
/// block. @throws pipeline::Error(io) if writing fails; `path` untouched on failure.
void write_fe_model(const FeModel& model, const std::string& path);

/// Tissue stack of one part, from the skin inward: (material, thickness [mm]).
using Stack = std::vector<std::pair<std::string, double>>;

/// Reads data/materials.json: head_layers_mm (kind "head") or respirator_layers_mm ("respirator",
/// returned under the part name "respirator_inner"). @throws Error(bad_input) naming the file for
/// a layer that is not [known material, 0.1..50 mm], more than 10 layers, a material twice in a
/// stack, a stack for back_of_head (a rigid shell), or a head stack whose innermost layer is not
/// rigid or that has a rigid layer above it.
std::map<std::string, Stack> read_stacks(const std::string& materials_json, const std::string& kind);

/// Checks that the surface's parts and the stacks match one to one: every part with a stack is a
/// triangle group of `surface`, and every triangle group but back_of_head (a rigid shell) has a
/// stack. A chin group renamed, or a chin missing from head_layers_mm, gave a head with no chin
/// layers and exit 0.
/// @throws Error(bad_input) naming `surface_path` for a missing group, `materials_path` for a
///         missing stack.
void require_stack_for_every_part(const FeModel& surface, const std::map<std::string, Stack>& stacks,
                                  const std::string& surface_path, const std::string& materials_path);

/// Checks that a head surface's left_cheek lies at mean x > 0 and its right_cheek at x < 0 (align's
/// frame: +x is the subject's left); groups absent are not checked. Names swapped by hand were
/// layered and assembled with the left cheek on the right, exit 0.
/// @throws Error(bad_input) naming `surface_path` and the cheek.
void require_cheeks_on_their_sides(const FeModel& surface, const std::string& surface_path);

/// Checks that the triangles of `surface` (all its triangle groups together) form one
/// edge-manifold, consistently oriented piece: every edge in at most two triangles, and in
/// opposite directions. surface_mesh writes such a surface; in an edited one a fin triangle, a
/// loose triangle, a second sheet or one flipped triangle ran 60 thinning passes (up to 14 s) and
/// ended as "wedges still inverted, distorted or intersecting".
/// @throws Error(bad_input) naming `surface_path` and an edge by its end points [mm].
void require_one_oriented_sheet(const FeModel& surface, const std::string& surface_path);

/// Checks that no triangle of `surface` repeats a node, has zero area or repeats another
/// triangle's three nodes. surface_mesh writes none; in an edited file a duplicated respirator
/// triangle was layered as two coincident wedges per layer, and a back_of_head triangle with a
/// repeated node was copied into the model, both with exit 0.
/// @throws Error(bad_input) naming `surface_path`, the group and the triangle's nodes (0-based).
void require_clean_triangles(const FeModel& surface, const std::string& surface_path);

/// Parses `layers --elements-per-tissue` ("fat=3,skin=2"): each name a material of `stacks`, each
/// count an integer in [1, 20] (the range of --elements-per-layer), no name twice.
/// @throws Error(usage) "--elements-per-tissue: 'fat=2.5', expected material=N with N an integer
///         1..20" or "... 'unobtainium=2': no layer of unobtainium in the stacks".
std::map<std::string, int> parse_elements_per_tissue(const std::string& text, const std::map<std::string, Stack>& stacks);

struct LayerOptions {
  std::string kind = "head";   ///< "head" (offset inward) or "respirator" (offset away from the face, +z)
  int elements_per_layer = 1;  ///< element layers through each tissue, [1, 20]
  std::map<std::string, int> elements_per_tissue;  ///< per-material override ("fat" → 3)
  /// Reach of the Laplacian smoothing of the offset directions [mm], [0, 100]: round((smoothing_mm /
  /// mean skin edge)²) passes, at most 200 (each diffuses ~one edge). 14 mm: 14 passes on the tests' 4 mm NIOSH
  /// surface (mean edge 3.7 mm), 6 / 5 on the chain's 6.4 / 7 mm surfaces. A fixed 10 passes
  /// smoothed the chain surfaces over ~20 mm, and a
  /// column leaning by θ from the surface normal gives a layer only t·cos θ thick: the forehead
  /// (nose) was the worst part × layer on all six chain heads, −4.4 % of mid-area × t at worst
  /// (issue 4: 5 %); a fixed 5 fixed that but failed the 4 mm NIOSH test (−5.4 %, too little
  /// smoothing at 4 mm). Figures: layering/README.md.
  double smoothing_mm = 14;
  double min_scaled_jacobian = 0.2;  ///< quality every wedge must reach, (0, 1)
  double ray_fraction = 0.4;   ///< column depth ≤ this × distance to the opposite surface, (0, 0.5]
  int max_fix_iterations = 60; ///< local thickness-reduction passes before giving up
};

/// Per part × layer: measured wedge volume against the nominal one.
struct LayerVolume {
  std::string group;
  std::size_t wedges = 0;
  double thickness = 0;        ///< nominal [mm]
  double volume = 0;           ///< Σ wedge volumes [mm³]
  double skin_area_volume = 0; ///< skin area × thickness [mm³] (ignores the shrinkage of inward offsets)
  double mid_area_volume = 0;  ///< area of the unreduced offset surface at mid-depth × thickness [mm³]
  /// The same two sums over the triangles whose three columns kept their full depth (scale 1):
  /// separates what the offset itself gives from what local thinning (the nose) takes away.
  double full_depth_volume = 0, full_depth_mid_area_volume = 0;
  double full_depth_area_fraction = 0;  ///< share of the part's skin area on full-depth triangles
};

struct LayerReport {
  std::size_t wedges = 0, shell_triangles = 0, nodes = 0;
  double min_scaled_jacobian = 0, min_volume = 0;  ///< over all wedges [–], [mm³]
  std::size_t reduced_columns = 0;     ///< columns whose depth was scaled down
  double min_depth_scale = 1;          ///< smallest column depth scale (1 = nominal)
  std::size_t intersecting_pairs = 0;  ///< element faces intersecting (0 on success)
  std::vector<LayerVolume> volumes;
};

/// The layer groups whose wedges hold more than `max_shortfall` (5 %, issue 4's target) less than
/// their mid-area × thickness, one warning line each, worst first: where a stack does not fit the
/// part's curvature the fix loop thins its columns, and a 30 mm cheek fat made the cheek's skin 23 %
/// thinner than the materials file asks, with exit 0 and no word. The chain's heads stay within
/// 4.4 % (the generated medium case head 3.9 %, the NIOSH heads 2.2 %).
/// @return e.g. "left_cheek_skin holds 22.9 % less than its mid-area x thickness (225 columns of
///         the model thinned where the stack does not fit)"
std::vector<std::string> volume_shortfall_warnings(const LayerReport& report, double max_shortfall = 0.05);

/// Offsets the face parts of a labelled surface into wedge layers.
///
/// @param[in] surface  triangles in blocks named after parts (forehead, left_cheek, right_cheek,
///                     chin, back_of_head; or respirator_inner), sharing boundary nodes
/// @param[in] stacks   part → tissue stack (read_stacks); parts without a stack stay shells
/// @param[in] opt      LayerOptions
/// @param[out] report  counts, quality, reductions, volumes
/// @return model with nodes (skin nodes first, same order as the input), one wedge block per
///   part × tissue ("<part>_<material>", "_layer" suffix dropped; respirator: "respirator_seal",
///   "respirator_outer"), the shell blocks unchanged, and surfaces: head — "head_skin" (all outer
///   triangles, outward), "<part>_skin_surface", "<part>_bone_inner"; respirator — "respirator_inner" and
///   "respirator_rim" (the inner face's border, lines; straps attach to it).
/// @throws Error(bad_input) no part with a stack, a non-triangle block, or a skin triangle whose own
///   shape already has scaled Jacobian < min; Error(algorithm) if the quality or the
///   intersection checks still fail after max_fix_iterations reductions.
FeModel build_layers(const FeModel& surface, const std::map<std::string, Stack>& stacks,
                     const LayerOptions& opt, LayerReport* report);

/// Scaled Jacobian of a gmsh-ordered wedge (Verdict's definition: min over the 6 corners of the
/// normalised corner determinant, × 2/√3 so that an equilateral right prism scores 1). ≤ 0 if inverted.
double wedge_scaled_jacobian(const Eigen::Vector3d* p);
/// Volume of a gmsh-ordered wedge [mm³] (3 tetrahedra; negative if inverted).
double wedge_volume(const Eigen::Vector3d* p);
/// Number of pairs of element faces (wedge triangles/quads split in two, shell triangles and
/// quads) of `model` that intersect other than along shared nodes (CGAL triangle soup test).
std::size_t count_intersecting_faces(const FeModel& model);

}  // namespace layering
