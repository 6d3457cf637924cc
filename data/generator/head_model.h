#pragma once
/// Parametric headform: an implicit surface (smooth union of ellipsoids, a tapered nose, a
/// tilted elliptic neck, minus the eye sockets) in the project frame (x lateral, +x = subject's
/// left, y up, z out of the face, mm), warped so that its measured dimensions (measure_head.h)
/// equal the requested ones, and meshed by casting rays from a point inside the head.
///
/// Why by hand: CGAL 5.5 has no isosurface extraction for a function other than the (slow to
/// compile, non-deterministic-size) Surface_mesher/Mesh_3. The head is star-shaped from its
/// centre, so one outermost root per ray over a subdivided icosahedron gives a closed
/// 2-manifold with sphere topology; its triangles lie in disjoint cones from the centre, so it
/// cannot self-intersect.
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "data/generator/measure_head.h"
#include "data/generator/scanner_artifacts.h"

namespace generator {

/// Anthropometric dimensions of a headform [mm], defined as in measure_head.h.
struct HeadParams {
  double face_length = 0;      ///< sellion–menton
  double face_width = 0;       ///< bizygomatic breadth
  double jaw_width = 0;        ///< bigonial breadth
  double head_breadth = 0;     ///< euryon–euryon
  double head_length = 0;      ///< glabella–opisthocranion
  double head_height = 0;      ///< vertex above sellion
  double nose_protrusion = 0;  ///< pronasale − subnasale (z)
  double nose_breadth = 0;     ///< alar breadth
};

/// Reads headform `id` from a params JSON ({"headforms": {"medium": {"face_length": ..}}}).
/// @throws Error(bad_input) naming the file: unreadable, not JSON, unknown id (listing the
///         known ones), a missing field or a value outside its plausible range.
HeadParams read_head_params(const std::string& path, const std::string& id);
/// The same from a params file already parsed (`path` names it in errors).
HeadParams head_params_from_json(const nlohmann::json& params, const std::string& path, const std::string& id);

/// The implicit head. value(p) < 0 inside, > 0 outside (not a distance).
class HeadShape {
 public:
  explicit HeadShape(const HeadParams& params);
  double value(const Point& p) const;
  /// The outermost surface point on the ray centre + t·dir (t > 0). dir need not be unit.
  Point ray_hit(const Vector& dir) const;
  /// The outermost surface point seen from far along −z at lateral position (x, y) (for the
  /// respirator rim), or false if the line misses the head.
  bool front_hit(double x, double y, Point* hit) const;
  /// True if every point of the segment a–b is certainly outside (value > 0), from lower bounds
  /// of each part over the segment's bounding box; false means "maybe not". Lets the ray
  /// marches skip lattice points without changing which one they stop at.
  bool provably_outside(const Point& a, const Point& b) const;
  /// Outward unit normal (normalised gradient) at p.
  Vector normal(const Point& p) const;
  /// Closed triangle mesh: icosahedron subdivided `level` times (level 7: 163,842 vertices).
  Triangles mesh(int level) const;
  /// Regions a structured-light scanner misses: under the chin and in both ears.
  std::vector<Hole> scanner_holes() const;
  Point centre() const { return centre_; }

 private:
  double base_value(const Point& q) const;  // unwarped medium-like design
  double sx(double qy) const;
  // Warp factors from the base design to the requested dimensions.
  double s_hb_ = 1, s_fw_ = 1, s_jw_ = 1, s_fl_ = 1, s_hh_ = 1, s_hl_ = 1, s_np_ = 1, s_nb_ = 1;
  Point centre_;
};

}  // namespace generator
