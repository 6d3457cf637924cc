#pragma once
/// Two respirator straps as bands of 4-node quadrilateral shells laid on the head (paper: top strap
/// high on the back of the head (occiput), bottom strap around the neck below the ears), each end
/// near its attachment point on the placed respirator's rim.
///
/// Defaults (assumptions, documented in meshing/README.md): length 300 mm unstretched for both
/// straps (the paper: "the two straps have the same lengths", measured but not reported; braided
/// N95 headbands are cut to roughly 28–33 cm), width 6 mm, thickness 1 mm (flat braided/elastic
/// N95 straps are ~5–7 mm wide, ~0.8–1.2 mm thick).
#include <map>
#include <string>

#include "layering/layers.h"
#include "meshing/assemble.h"

namespace meshing {

/// The straps' clearance over the skin [mm] (plus half their thickness): StrapOptions's default,
/// which the straps program keeps (it has no option for it), and the height over the skin at
/// which assemble's stage I deck brings the strap ends to their attachments.
inline constexpr double strap_clearance_mm = 1;

struct StrapOptions {
  double length_mm = 300;     ///< unstretched length of each strap along its centre line [mm], [50, 1000]
  double width_mm = 6;        ///< band width [mm], [1, 30]
  double thickness_mm = 1;    ///< shell thickness [mm]: sets the clearance below; the decks take assemble's own value
  // element_mm, clearance_mm and the two heights below have no option in the straps program:
  // the pipeline's straps always have them (library users may change them).
  double element_mm = 3;      ///< target element length along the strap [mm]
  double clearance_mm = strap_clearance_mm;  ///< least distance of the band's mid-surface to the skin [mm] (+ half the thickness)
  /// Largest stretch [% of length_mm] the head's outline between the attachments may ask of a
  /// strap. The 300 mm default is stretched 46–62 % (top) and 14–43 % (bottom) on the five
  /// generated heads, and the strap material is linear elastic; a 50 mm strap (a length in cm
  /// typed as mm?) would be stretched ~830 %, and was laid without a word.
  double max_stretch_percent = 100;
  double top_above_sellion_mm = 25;   ///< height of the top strap at the back, above the sellion [mm]
  double bottom_below_menton_mm = 5;  ///< height of the bottom strap at the back of the neck, below the menton
  PlaceOptions place;         ///< where assemble puts the respirator (attachment points follow it)
};

struct StrapReport {
  double top_length = 0, bottom_length = 0;  ///< measured centre-line lengths [mm]
  /// The head's outline between each strap's attachment points (offset by the strap's lift): the
  /// least length the strap is stretched to when worn [mm].
  double top_outline = 0, bottom_outline = 0;
  double min_gap = 0;                        ///< minimum signed distance of any strap node to the skin [mm]
  Eigen::Vector3d min_gap_at = Eigen::Vector3d::Zero();  ///< the strap node where min_gap is measured [mm]
  std::size_t quads = 0;
  double top_back_y = 0;  ///< height of the top strap's point on the back of the head [mm]
};

/// Lays both straps. The strap plane passes through the two attachment points and a point on the
/// back of the head; the strap follows the convex hull of the skin within the slab the band
/// occupies (projected onto that plane, band across = the plane's normal), offset outward by
/// `clearance_mm + thickness/2`, and is centred on the back of the head.
/// @return groups strap_top, strap_bottom (quads), strap_<s>_end_<side> (2-node lines across each end),
///   strap_<s>_attach_<side> (one point each: the attachment point on the placed rim); side left = +x.
/// @throws Error(bad_input) if a strap, centred on the back of the head, runs past an attachment
///         (longer than twice the outline from the back to the nearer attachment), or so short that the outline stretches it more than `max_stretch_percent`.
layering::FeModel make_straps(const layering::FeModel& head, const std::map<std::string, Eigen::Vector3d>& lm,
                              const layering::FeModel& resp, const StrapOptions& opt, StrapReport* report);

}  // namespace meshing
