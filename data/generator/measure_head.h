#pragma once
/// Automatic anthropometric measurement of a head surface in the project frame (x lateral,
/// y up, z out of the face, mm, sagittal plane x = 0). Used to measure the real NIOSH headforms
/// (whose values size the generated ones, see README.md) and to check the generated heads.
///
/// Definitions (the same code measures both, so they are comparable):
/// - sagittal profile: intersections of the mesh edges with the plane x = 0, front part (z > 0);
/// - pronasale: most anterior (max z) profile point;
/// - sellion: the profile point with y in [pronasale.y + 10, pronasale.y + 70] deepest below
///   the chord from the pronasale to the forehead profile point at pronasale.y + 70;
/// - glabella: max z of the profile with y in [sellion.y, sellion.y + 40];
/// - subnasale: min z of the profile with y in [pronasale.y − 25, pronasale.y − 5];
/// - menton: the lowest profile point (min y) below pronasale.y − 40 with z ≥ pronasale.z − 50
///   (the bottom of the chin, not the throat or the neck cut);
/// - face_length: |sellion − menton|;
/// - face_width (bizygomatic): 2·max|x| of vertices with y in [pronasale.y, sellion.y] and
///   z ≥ sellion.z − 100 (in front of the ears);
/// - jaw_width (bigonial): 2·max|x| of vertices with y in [menton.y + 15, menton.y + 35] and
///   z ≥ sellion.z − 100;
/// - head_breadth: 2·max|x| of vertices above sellion.y + 25 (above the ears);
/// - head_length: glabella.z − min z of the profile with y ≥ sellion.y − 20;
/// - head_height: max y − sellion.y;
/// - nose_protrusion: pronasale.z − subnasale.z;
/// - nose_breadth: 2·max|x| of vertices with y in [subnasale.y, pronasale.y] and
///   z ≥ subnasale.z − 8.
#include <string>

#include "data/generator/scanner_artifacts.h"

namespace generator {

struct HeadDimensions {
  Point pronasale, glabella, sellion, subnasale, menton;  ///< landmarks [mm]
  double face_length = 0, face_width = 0, jaw_width = 0, head_breadth = 0, head_length = 0,
         head_height = 0, nose_protrusion = 0, nose_breadth = 0;  ///< [mm]
};

/// Measures a head surface given in the project frame.
/// @throws Error(bad_input) naming `what` if a landmark cannot be found (not a head, or not in
///         the frame).
HeadDimensions measure_head(const Triangles& head, const std::string& what = "head");

}  // namespace generator
