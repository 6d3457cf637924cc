#pragma once
/// Five-part segmentation of an aligned head (paper Fig. 3c) and inner-face extraction of an
/// aligned respirator shell, for `segment`.
///
/// Head parts (face property "f:part"; the labels of the Part enum below, which fit and the
/// physical group names of surface_mesh follow):
///   back_of_head 0, forehead 1, left_cheek 2 (x > 0, subject's left), right_cheek 3, chin 4.
/// The parts are cut along zero level sets of smooth fields built from the landmarks (planes
/// blended with a smooth maximum, a parabola, the sagittal plane), so part boundaries are smooth
/// curves across the triangles, not staircases along mesh edges:
///   face region  = in front of a coronal plane just behind the zygia (but at least 0.25 of the
///                  sellion–tragion depth in front of the tragia), above a plane through both
///                  gonia and a point under the chin (keeps the under-chin, drops the neck), below
///                  the upper forehead (sellion + 0.45 face length); corners rounded (radius 8 mm);
///   forehead     = face region above a line 0.15 face length below the sellion (upper forehead,
///                  eyes), united with the nose: the nasal bridge and the whole nose, its underside
///                  included, down to 0.5 nose height (sellion–pronasale) below the pronasale on
///                  the midline, just below the subnasale, dipping to 0.75 nose height at the alae
///                  (below the alar bases), between the cheek–nose folds at |x| = 0.09 zygion breadth at the
///                  sellion widening linearly to 0.145 zygion breadth at the pronasale level (the
///                  alae); nose corners rounded (6 mm), the nose–forehead junction filleted (4 mm).
///                  The nose goes to the forehead's thin stack (skin 5 + bone 2 mm): an 18 mm cheek
///                  stack does not fit under a ~20 mm wide nose;
///   chin         = face region below a parabola through the mouth level (menton + 0.35 face
///                  length) on the midline and the gonia laterally (includes the under-chin);
///   cheeks       = the rest of the face region, split by the sagittal plane x = 0.
/// Islands (components of a label other than its largest) are merged into their neighbours.
#include <array>
#include <vector>

#include "pipeline/surface_mesh.h"

namespace layering {

using Vec3 = std::array<double, 3>;

/// Landmarks in the head frame (x lateral, +x = subject's left; y up; z out of the face) [mm].
struct HeadLandmarks {
  Vec3 sellion{}, pronasale{}, menton{};
  Vec3 zygion_left{}, zygion_right{};
  Vec3 tragion_left{}, tragion_right{};
  Vec3 gonion_left{}, gonion_right{};
};

/// Part labels ("f:part").
enum Part : int { back_of_head = 0, forehead = 1, left_cheek = 2, right_cheek = 3, chin = 4 };
/// Label of the single kept part of a respirator (its inner face; physical group respirator_inner).
inline constexpr int respirator_inner = 0;
/// Name of a head part label ("forehead", ...), as used for physical groups.
const char* part_name(int label);

/// Topology and size of one labelled part.
struct PartStats {
  int label = 0;
  std::size_t faces = 0;
  double area_mm2 = 0;     ///< [mm²]
  int euler = 0;           ///< V − E + F of the part's faces (1 for a disk)
  int boundary_loops = 0;  ///< closed boundary curves (1 for a disk)
};

/// Labels the faces of an aligned, closed (or open) triangulated head with the five parts.
///
/// @param[in,out] mesh  triangle mesh in the head frame [mm]; it is refined along the part
///                      boundaries (new vertices on the cut curves) and gets the int face
///                      property "f:part"
/// @param[in]     lm    landmarks in the same frame
/// @return stats of the five parts, indexed by label
/// @throws pipeline::Error(algorithm) if a face part comes out empty (landmarks not on this head)
/// @note O(#F); about 0.1 s for 20k triangles
std::vector<PartStats> segment_head(pipeline::SurfaceMesh& mesh, const HeadLandmarks& lm);

/// What segment_respirator found.
struct RespiratorSegmentInfo {
  bool thin_shell = false;     ///< closed (or nearly) thin shell; false: taken as one open sheet
  double wall_mm = 0;          ///< wall thickness: median distance to the opposite sheet [mm]
  double paired_fraction = 0;  ///< share of faces with an opposite-sheet partner
  std::size_t faces_dropped = 0;  ///< faces not of the inner face: the outer sheet, the edge strip, rim teeth
};

/// Keeps the inner face (the side toward the face, −z, bounded by its rim) of an aligned
/// respirator: every other face is removed, the kept faces get "f:part" = respirator_inner.
///
/// Thin shell (a closed surface around a wall of a few mm, as a reconstruction or the
/// generator's clean mesh): the shell is oriented outward; each face is paired with the opposite
/// sheet (first hit of a ray from its centre along −normal, facing within 45° of opposite, within
/// 8 × the median hit distance = the wall thickness); of a pair, the face that faces the cavity is
/// inner: the one that sees more of the shell (share of 24 rays over the hemisphere of its normal
/// that hit it; near-ties go to the face looking toward −z). Faces of the strip that joins the
/// two sheets along the edge of the cup have no near partner and are dropped, so the rim is the
/// inner sheet's edge. If fewer than half of the faces pair, the input is one open sheet: all of
/// it is kept, oriented toward −z. Then islands of either side are merged, and the rim is made
/// smooth (teeth and notches one triangle deep removed). A frame open at both ends (the real
/// face-seal parts) gives an annulus (two rims), not a disk.
/// @param[out] info  optional: shell or sheet, wall thickness, paired share
/// @throws pipeline::Error(bad_input) on an empty mesh, or an inner face that is not a sheet (no
///         rim: a capped cup; handles: walls merged into one); Error(algorithm) if no inner face
///         is found
PartStats segment_respirator(pipeline::SurfaceMesh& mesh, RespiratorSegmentInfo* info = nullptr);

/// Refuses an inner face of a respirator that is not a sheet: one with no rim (a capped cup) or
/// with handles (2 − χ − rims > 0: the two walls of a scan merged into one). A disc (a cup) and
/// a ring (a frame with a port hole, the real parts) pass. Called by segment_respirator.
/// @throws pipeline::Error(bad_input) "respirator: its inner face is closed (no rim): ..." or
///         "respirator: its inner face has 57 handles (Euler characteristic -113, 1 rim(s)), ..."
void require_respirator_sheet(const PartStats& inner);

/// Topology of the faces labelled `label` in "f:part".
/// @throws pipeline::Error(bad_input) if the mesh has no "f:part" property
PartStats part_stats(const pipeline::SurfaceMesh& mesh, int label);

}  // namespace layering
