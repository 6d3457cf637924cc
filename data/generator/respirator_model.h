#pragma once
/// Parametric N95 filtering facepiece: a domed cup whose rim lies on an average face (over
/// the nasal bridge, along the cheeks, at the bottom of the chin), as a thin closed shell in the
/// head frame (symmetric about x = 0, concave side toward −z, i.e. toward the face).
///
/// Construction: the rim outline is an egg shape of the given width and height in the x–y
/// plane, from just below the sellion of the face down to the menton; each rim point is put
/// on the face (ray along −z). The inner surface over the polar grid of the outline is the
/// rim height blended inward plus a dome D·(1 − ρ²)^0.7, with D at least `depth` and large
/// enough to clear the face (nose) by `clearance`; the outer surface is the inner one moved by
/// `wall` along its normal (away from the face; the dome is convex seen from outside, so the
/// offset cannot fold), and a strip closes the rim: a closed 2-manifold of constant thickness.
#include <string>

#include "data/generator/head_model.h"

namespace generator {

struct RespiratorParams {
  double width = 0;         ///< rim breadth, cheek to cheek [mm], 80..180
  double height = 0;        ///< rim height, nasal bridge to chin [mm], 80..170
  double depth = 0;         ///< minimum dome depth in front of the rim [mm], 20..90
  double wall = 1.5;        ///< shell thickness along the normal [mm], 0.5..4
  double clearance = 8.0;   ///< minimum gap between inner shell and the face inside the rim [mm]
  double nose_drop = 5.0;   ///< top of the rim below the sellion [mm]
};

/// Reads respirator `id` ({"respirators": {"onesize": {"width": .., ...}}}) and the average
/// face it sits on ({"headforms": {"average": {...}}} in the same file).
/// @throws Error(bad_input) naming the file (unknown id listing the known ones, missing or
///         implausible value).
RespiratorParams read_respirator_params(const std::string& path, const std::string& id,
                                        HeadParams* face);

/// The rim as built [mm]: its breadth in x and its height in y, seen from the front.
struct RimSize {
  double width = 0, height = 0;
};

/// Builds the closed shell on `face`; `rim` (optional) gets the rim's size as built, which falls
/// short of p.width and p.height where the face does not reach: the rim stays on the front of
/// the face (normal·z ≥ 0.35) and between p.nose_drop (5 mm) below the sellion and 2 mm above the
/// menton (on the average face at most ~106 mm high). @throws Error(algorithm) if the rim misses the face.
Triangles make_respirator(const RespiratorParams& p, const HeadShape& face, RimSize* rim = nullptr);

}  // namespace generator
