#pragma once
/// Symmetric hole completion: the faired fills of a nearly mirror-symmetric surface (a head) are
/// reshaped after the mirror image of the scanned surface on the other side of its symmetry
/// plane.
///
/// Why: a fill faired from its border (fill_holes) continues the surface smoothly, so a scan hole
/// over a feature nobody scanned comes out flat: on the generated heads a 14.5 mm hole over the
/// eye socket was filled 2.2 mm above it, one beside the nose 1.2 mm off. A head is close to
/// mirror symmetric, and the other side of the face was usually scanned there. No library does
/// this (CGAL has neither a symmetry detector nor a symmetry-guided fill), so it is written here,
/// with CGAL's AABB tree for the closest points and Eigen's sparse Cholesky for the blends.
///
/// Method, once for the surface and then per filled hole:
///  1. the plane of best mirror symmetry of the whole surface (align's detector,
///     internal::find_symmetry_plane); no hole is changed when the surface is not symmetric
///     enough (plane RMS above max_plane_rms_mm or inliers below min_plane_inliers);
///  2. each fill vertex's mirror image is matched to the closest point of the surface. The match
///     counts when it lies on a scanned face (not on any fill), within max_mirror_distance_mm of
///     the mirror image, on a face turned like the mirrored vertex normal (within 60°). The mirror
///     image of the match is then the vertex's target, d = mirror(match) − vertex;
///  3. a band of scanned vertices along the fill's border (border_band_rings) is treated like the
///     fill (a reconstructed border is extrapolated); on the ring_width rings outside the band,
///     d measures how symmetric the surface is there: the local asymmetry. A hole whose
///     reference rings are not symmetric (RMS |d| above max_ring_asymmetry_mm, or fewer than
///     half of them matched) keeps its faired fill;
///  4. the reference rings' d is carried into the hole smoothly (harmonic interpolation) and
///     subtracted from the band's and fill's d, so the completed fill meets the surface around
///     it without a step, as seamless cloning does with images. Vertices without a match (their
///     mirror image lies in a fill, e.g. in a hole across the symmetry plane) move by a harmonic
///     blend of their neighbours' moves, the reference rings' being zero.
/// Limitation: an asymmetric feature (a scar, a mole) on the other side is copied into a hole
/// over a place that does not have it; the ring test only catches broad asymmetry.
#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/surface_mesh.h"

namespace scan2cad {

struct SymmetricCompletionOptions {
  /// farthest a fill vertex's mirror image may be from the scanned surface it is matched to
  /// [mm]; default 4 (a faired fill is up to ~2.5 mm off where this is needed)
  double max_mirror_distance_mm = 4.0;
  /// largest RMS asymmetry of a hole's scanned ring for the hole to be completed [mm]; default 0.5
  double max_ring_asymmetry_mm = 0.5;
  /// rings of scanned vertices along a fill's border that move with the fill; default 2. A hole
  /// cut out of a Poisson surface keeps Poisson's extrapolation up to 2 point spacings past the
  /// last points (reconstruct's hole cut): on the generated medium head's eye-socket hole a
  /// border vertex was 1.15 mm off the surface
  int border_band_rings = 2;
  /// the next rings outward, which measure the local asymmetry; default 3
  int ring_width = 3;
  /// the surface's symmetry must be at least this good: RMS mirror distance [mm], default 1.0,
  /// and share of the surface matching its mirror image, default 0.9 (the NIOSH and generated
  /// heads: 0.11 mm and 0.975-0.988)
  double max_plane_rms_mm = 1.0;
  double min_plane_inliers = 0.9;
};

/// What happened to one filled hole.
struct SymmetricHoleCompletion {
  std::size_t fill_vertices = 0;      ///< vertices the fill added
  std::size_t mirrored_vertices = 0;  ///< of them, with a match on the scanned other side
  std::size_t band_vertices = 0;      ///< scanned vertices along the border that moved with it
  std::size_t ring_vertices = 0, ring_matched = 0;  ///< the reference rings outside the band
  double ring_asymmetry_rms_mm = 0;   ///< RMS |d| over the matched ring vertices [mm]
  bool completed = false;             ///< the fill was reshaped
  double max_move_mm = 0, mean_move_mm = 0;  ///< over the fill and band vertices [mm]
};

struct SymmetricCompletionReport {
  bool plane_found = false;
  Eigen::Vector3d plane_normal = Eigen::Vector3d::UnitX();  ///< unit normal n of {x : n·x = d}
  double plane_offset_mm = 0;                               ///< d [mm]
  double plane_rms_mm = 0, plane_inliers = 0;
  std::string skipped;  ///< why no hole was completed, or empty
  std::vector<SymmetricHoleCompletion> holes;  ///< one per fill, in the order given

  nlohmann::json to_json() const;
};

/// Reshapes the given hole fills of `mesh` after the mirrored scanned surface (method above).
///
/// @param[in,out] mesh   closed or open triangle mesh [mm] whose holes were filled
/// @param[in]     fills  #H lists of the faces each fill added (fill_holes' `fills`)
/// @param[in]     opt    SymmetricCompletionOptions
/// @return what was done per hole; nothing is changed (and `skipped` says why) when the mesh is
///         not symmetric enough or no fill was given
/// @note only fill vertices and the band of scanned vertices around each fill move (Method,
///       step 3); the connectivity is unchanged. Never throws on a surface
///       without a symmetry plane: it is then skipped.
SymmetricCompletionReport complete_fills_by_symmetry(pipeline::SurfaceMesh& mesh,
                                                     const std::vector<std::vector<pipeline::FaceIndex>>& fills,
                                                     const SymmetricCompletionOptions& opt = {});

}  // namespace scan2cad
