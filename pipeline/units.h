#pragma once
/// Length units of scans. The whole project works in mm (DESIGN.md); a scan in another unit is
/// scaled once, when it is read.
#include <algorithm>
#include <cstddef>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace pipeline {

/// Real largest bounding-box extents of the objects the pipeline handles [mm]: a head with its
/// neck, a respirator cup. Unit detection, and the mm check of the stages after align, compare
/// sizes with these.
inline constexpr double head_extent_mm = 250.0;
inline constexpr double respirator_extent_mm = 130.0;

/// No adult head is under 0.6 of head_extent_mm (150 mm) and no respirator under 0.6 of
/// respirator_extent_mm (78 mm): a guessed unit that gives less is not taken (detect_unit), and
/// reconstruct refuses a cloud of a detected unit that spans less once its outliers are gone.
inline constexpr double smallest_real_share_of_extent = 0.6;

/// Nor is any over 1.6 of it: a head with its neck is 285-302 mm (NIOSH medium, large), 400 mm is
/// a bust; a respirator 112-133 mm (the generated and the shared cups), 208 mm is a head given as a
/// respirator (285 mm), which passed reconstruct, repair and align before segment refused it.
/// Checked once the outliers (reconstruct) or the debris (repair) are gone, not on the file's box:
/// one stray point a metre off is a scanner's, not the object's.
inline constexpr double largest_real_share_of_extent = 1.6;

/// An object's size against its kind's real range, smallest_real_share_of_extent to
/// largest_real_share_of_extent times expected_extent_mm(kind), for stages that read one whole
/// surface as that kind (align, landmarks): a head given as a respirator was aligned as one (288 mm),
/// a respirator given to landmarks failed as "no ear region", and a vertex 3 m off a head ended
/// align as "cannot tell up from down".
/// @param extent_mm    the object's largest bounding-box extent [mm]
/// @param kind_option  the stage has --kind (the message then points to it)
/// @throws Error(bad_input) naming `path`: "it spans 288.4 mm, over the 208 mm of the largest
///         respirator: a vertex far off (repair removes spikes and debris), or an object of another
///         kind (see --kind)?", or "... under the 150 mm of the smallest head: ...".
void require_real_size(const std::string& path, double extent_mm, const std::string& kind, bool kind_option = true);

/// The question that ends a refusal of a scan's size (unit detection, reconstruct, repair):
/// "an object of another kind (see --kind), or in another unit (see --unit)? align refuses an
/// object of that size"; `too_large` adds "more than the object (shoulders, a stand: crop ...)"
/// before the unit (a head scanned with its shoulders, sweep O).
std::string wrong_size_question(bool too_large);

/// head_extent_mm for "head", respirator_extent_mm for "respirator". @throws Error(usage) otherwise.
double expected_extent_mm(const std::string& kind);

/// Largest extent of the axis-aligned bounding box of `points`, any range of points with p[0..2]
/// (CGAL points, Eigen vectors) [same unit as the points]; 0 for no points.
template <class PointRange>
double largest_extent(const PointRange& points) {
  double lo[3], hi[3];
  std::fill(lo, lo + 3, std::numeric_limits<double>::infinity());
  std::fill(hi, hi + 3, -std::numeric_limits<double>::infinity());
  bool any = false;
  for (const auto& p : points) {
    any = true;
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], double(p[k])), hi[k] = std::max(hi[k], double(p[k]));
  }
  return any ? std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}) : 0.0;
}

/// The largest extent of `points` that unit detection and the size checks on a file compare with
/// an object's: the bounding box's, unless a few far points stretch the box to more than 1.25
/// times the bulk's (per axis, the span of the 0.5th to 99.5th percentile of the coordinates),
/// and then the bulk's. One stray point or speck of debris a metre off (a scanner's, removed later
/// as an outlier or a small component) made a head 4.4 m across, refused whatever --unit said.
/// Without far points the box's extent, as largest_extent.
template <class PointRange>
double extent_without_far_points(const PointRange& points) {
  const double box = largest_extent(points);
  std::vector<double> c;
  double bulk = 0;
  for (int k = 0; k < 3; ++k) {
    c.clear();
    for (const auto& p : points) c.push_back(double(p[k]));
    if (c.empty()) return 0;
    const std::size_t lo = std::size_t(0.005 * double(c.size())), hi = c.size() - 1 - lo;
    std::nth_element(c.begin(), c.begin() + std::ptrdiff_t(lo), c.end());
    const double low = c[lo];
    std::nth_element(c.begin(), c.begin() + std::ptrdiff_t(hi), c.end());
    bulk = std::max(bulk, c[hi] - low);
  }
  return box > 1.25 * bulk ? bulk : box;
}

enum class Unit { automatic, mm, cm, m, inch };

/// Parses "auto", "mm", "cm", "m" or "in". @throws Error(usage) otherwise.
Unit parse_unit(const std::string& name);
std::string unit_name(Unit u);
/// Millimetres per unit (mm → 1, m → 1000). `automatic` is not a unit: throws.
double mm_per_unit(Unit u);

/// Guesses the unit of an object whose largest bounding-box extent is `extent` (in file
/// units), knowing that it is `expected_mm` long in reality (a head ≈ 250 mm, a respirator
/// ≈ 130 mm). Accepts a unit when the implied size is within a factor 4 of expected_mm.
///
/// @param[in] what  file name for the error message
/// @return mm, cm or m
/// @throws Error(bad_input) when no unit gives a plausible size (e.g. a 3 km "head"), when the
///         first plausible size is under 0.6 of expected_mm (in cm: it could be inches, a head in
///         inches; in mm or m: an object of another kind, a respirator given as a head), or extent
///         is not positive and finite.
Unit detect_unit(double extent, double expected_mm, const std::string& what);

/// One log line on the unit a file was read in and the size that gives, so that a wrong guess
/// shows: "unit cm (detected, --unit forces one): largest extent 285.7 mm (a head is about 250)".
/// A size that could be cm or inches (a factor 2.54) is refused by detect_unit, not guessed.
/// @param extent_mm  largest bounding-box extent after scaling [mm]
/// @param object     what the file holds ("head", "respirator")
std::string describe_unit(Unit unit, bool detected, double extent_mm, const std::string& object, double expected_mm);

/// A unit given with --unit is checked as detection would check its guess: the size it gives must
/// be within a factor 4 of the object's (a head in mm read with --unit m came out 328 m across
/// and was reconstructed with a 1.3 m spacing, exit 0).
/// @param extent_mm  largest bounding-box extent after scaling by `unit` [mm]
/// @throws Error(bad_input) "<path>: read in m (--unit), its largest extent is 328163 mm, but a
///         head is about 250 mm: is the unit right?"
void require_forced_unit_plausible(const std::string& path, Unit unit, double extent_mm, const std::string& object,
                                   double expected_mm);

/// The stages after align read files in mm only (align detects and converts the unit of a scan).
/// A file in m, cm or inches given to them otherwise fails far from its cause: no chin found, a
/// 10-triangle "fit" written with exit 0, 60 layer-thinning passes. This checks the size the way
/// detect_unit does: the largest extent must be within a factor 4 of the object's real size.
///
/// @param[in] path       file the object was read from, for the message
/// @param[in] extent_mm  largest bounding-box extent of what it holds, taken as mm
/// @param[in] kind       "head" or "respirator": the expected size
/// @param[in] object     what the file holds, as a noun for "a <object>" in the message (default:
///                       `kind`), e.g. "head's strap set": straps span a head and are sized like one
/// @throws Error(bad_input) naming `path` when the size is implausible in mm.
void require_mm(const std::string& path, double extent_mm, const std::string& kind, const std::string& object = "");

/// Density bounds of the project's materials [g/mm³; units mm, ms, g, N, MPa]. A density given
/// in g/cm³ (the paper's tables) or kg/m³ is 1e3 or 1e6 times too large, and a run with it is
/// sound but wrong; every solid and foam lies within these.
inline constexpr double min_density_g_mm3 = 1e-6;  // 1 kg/m³, lighter than any foam
inline constexpr double max_density_g_mm3 = 0.1;   // 100 g/cm³, four times osmium

/// The stiffest a material may be [MPa]: twice diamond's 1.05e6. E 1e300 went through assemble
/// and made solve ask for 9e153 steps; bone is 1e3, a bone E given in Pa 1e9.
inline constexpr double max_E_MPa = 2e6;

/// The strongest mass-proportional damping alpha (c = alpha m) [1/ms]: the decks use 0.5; above
/// 1000 a velocity dies within a microsecond and the run stands still (1e12 ran with exit 0).
/// Shared by assemble (data/materials.json's damping) and solve (control.damping_alpha).
inline constexpr double max_damping_alpha_per_ms = 1000;

/// Why a material cannot be used, or "" when it can: density within the bounds above, E > 0
/// and at most max_E_MPa, nu in [0, 0.5). Shared by assemble (data/materials.json) and solve (its
/// deck), so a unit slip stops at the first stage that reads it.
std::string why_material_unusable(double density_g_mm3, double E_MPa, double nu);

/// The keys a material object holds, in data/materials.json and in a solve deck (assemble copies
/// one into the other); any other key is refused by both readers.
inline const std::set<std::string> material_keys = {"density", "E", "nu", "rigid"};

}  // namespace pipeline
