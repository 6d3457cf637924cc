#pragma once
/// Surface mesh for layering: a conforming, part-wise triangle mesh of a fitted (or segmented)
/// surface, as a gmsh model with one named 2D physical group per part.
///
/// The triangles come from scan2cad::remesh_parts (CGAL isotropic remeshing with the part cuts
/// constrained) at the layering size, the back of the head coarser, the worst triangles then
/// improved (scan2cad::improve_triangles: flips, angle smoothing); gmsh then holds them as
/// discrete surfaces sharing their boundary nodes and curves (createTopology). The triangles are
/// rated with gmsh's "gamma" as scan2cad::triangle_gamma computes it (gmsh 4.8's API has no
/// getElementQualities). gmsh's own re-meshing of parametrized parts is not used: it
/// fails on the back of the head (see scan2cad/fit.h).
#include <string>
#include <vector>

#include "pipeline/progress.h"
#include "pipeline/surface_mesh.h"

namespace meshing {

/// The CLI defaults. Face parts / respirator: chosen so that the layered generated medium head
/// lands near the paper's 13,570 pentahedra - its chain (make case=medium_onesize) gave 13,484
/// wedges at 6.4 mm when chosen (2026-11-23), 13,049 on 2026-12-06 (13,350 at 6.3, 13,571 at
/// 6.25, 10,814 at 7). back_of_head is a rigid shell with no wedges, so
/// it stays coarser; 7 vs 6.4 leaves the cut's triangles good (gamma >= 0.5 on all six heads).
inline constexpr double default_size_mm = 6.4;
/// The most triangles `surface_mesh` asks for (pipeline::require_affordable_edge): ~100 times the
/// default head; --size 0.5 on a head (~1.2 million) ran for minutes past 1 GB.
inline constexpr double max_surface_mesh_triangles = 1e6;
inline constexpr double default_back_size_mm = 7.0;

/// back_of_head's size against the face parts': at the cut between them too large a ratio leaves
/// no good triangle at any size. The generated medium head (sizes in mm, face / back): 2 / 7
/// failed at all seven sizes (251 s, 808 MB), 1 / 7 and 2 / 6 ran past 300 s; 2 / 4, 2 / 5,
/// 1.5 / 3.75, 1.5 / 4.5, 1 / 2.5 and 1 / 3 mesh in 5, 5, 10, 8, 30 and 25 s (2.5 / 7 after one
/// retry). Without --back-size the back gets min(default_back_size_mm, back_size_ratio x size),
/// never finer than the size; a --back-size over max_back_size_ratio times --size is refused.
inline constexpr double back_size_ratio = 2.0;
inline constexpr double max_back_size_ratio = 2.5;
/// The back size used when none is given: min(7, 2 x size_mm), at least size_mm.
double default_back_size_for(double size_mm);

struct SurfaceMeshPart {
  std::string name;
  std::size_t triangles = 0;
  double min_gamma = 0, mean_gamma = 0;  ///< gmsh's "gamma", 2·r_in/r_circ (1 = equilateral)
};

/// How surface_mesh retries when a size gives a triangle below min_gamma: each retry's sizes are
/// the last ones times retry_size_factor, at most default_max_retries times (a quarter of the size).
inline constexpr double retry_size_factor = 0.8;
inline constexpr int default_max_retries = 6;

/// What surface_mesh did when the asked size gave a triangle below min_gamma.
struct SurfaceMeshRetries {
  double size_mm = 0, back_size_mm = 0;  ///< the sizes the returned mesh was made with
  std::vector<std::string> failed;       ///< one line per size that failed, and where
};

/// Builds the surface mesh in the CURRENT gmsh model (gmsh initialized by the caller). Where two
/// constrained lines run closer than the size (the real Conforming cup's 1 mm rib: gamma 0.16 at
/// 6.4 mm; the real Flex face seal's rim and a crease 4 mm from it), no triangle between them is
/// good; the mesh is then made again with both sizes retry_size_factor (0.8) times theirs, up to
/// `max_retries` times (the Conforming cup passes at 4.1 mm, the Flex seal at 2.6), but never to a
/// size at which the whole surface would hold more than `max_triangles`.
/// Each attempt takes well under a second on a respirator.
/// @param[in] fitted       triangle mesh [mm] with int face property "f:part"
/// @param[in] kind         "head" or "respirator" (one part, respirator_inner)
/// @param[in] size_mm      target edge length on the face parts / the respirator [mm]
/// @param[in] back_size_mm target edge length on back_of_head [mm] (head only)
/// @param[out] retries     if given: the sizes used and the failed attempts
/// @param[in] progress     if given: a line per attempt, as it starts, and per failed attempt
/// @param[in] max_triangles the retries' budget: the whole surface's area over a triangle's
/// @return per part: triangle count and quality
/// @throws pipeline::Error(bad_input) on missing/unknown part labels; Error(algorithm) if gmsh fails
///         or the minimum gamma is below `min_gamma` after the last retry
std::vector<SurfaceMeshPart> surface_mesh(const pipeline::SurfaceMesh& fitted, const std::string& kind,
                                          double size_mm, double back_size_mm, double min_gamma = 0.3,
                                          int max_retries = default_max_retries, SurfaceMeshRetries* retries = nullptr,
                                          pipeline::Progress* progress = nullptr,
                                          double max_triangles = max_surface_mesh_triangles);

}  // namespace meshing
