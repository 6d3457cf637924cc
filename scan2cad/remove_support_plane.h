#pragma once
/// Finds the table, turntable or board a scanned head or respirator stood on and removes its
/// points, before reconstruct meshes them.
///
/// A headform scanned on a table comes with a patch of the table around its neck. Poisson then
/// failed on it (NIOSH medium 20 mm above a 280 mm disc: CGAL's surface mesher asserted, "is
/// already inserted on surface", after 50 s), and a mesh of head and table would not have been a
/// head anyway.
///
/// A support is a plane of points (CGAL's efficient RANSAC on a subsample) that
///   1. has the object on one side only: at most max_other_side_share of the points off the
///      plane lie on its far side (a plane through a head cuts it), and
///   2. reaches beyond the object: at least min_beyond_share of its points lie more than
///      outline_gap_mm outside the object's outline on it, the convex hull of the other points
///      projected onto the plane. A headform's flat neck cap (NIOSH medium's, 135 mm across) and
///      a generated cup's flat part lie within the outline and are kept; a table shows around it;
///   3. is as wide as the object: its points span at least min_outline_width_share of the
///      outline's larger side (in the plane's own axes). A cup's side past a large scan hole
///      reached 27 % beyond it.
/// Removed are every point beyond the plane, every point within its contact band (the table's own
/// noise: the table, and a neck cap that stands on it; repair closes the neck again), and the
/// points within the wider removal band (a table not quite flat) except where the object stands
/// on the table: near its footprint, the outline of its points just above the removal band. There
/// the object keeps its points above the contact band: a generated cup standing on its rim lost
/// up to 3.7 mm of the rim when the removal band applied everywhere.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/surface_mesh.h"

namespace scan2cad {

struct SupportPlaneOptions {
  /// points the plane is searched on, spread evenly over the input (all when fewer)
  std::size_t sample_points = 20000;
  /// RANSAC: largest distance of a plane's point [mm]; a plane must hold min_plane_share of the
  /// sample
  double ransac_epsilon_mm = 1.0;
  double min_plane_share = 0.03;
  double max_other_side_share = 0.01;
  double outline_gap_mm = 10.0;
  double min_beyond_share = 0.2;
  /// the plane's points span at least this share of the object's outline on it (in its axes)
  double min_outline_width_share = 1.0;
  /// outside the object's outline (by more than outline_margin_mm), points within max(this,
  /// 4 × the plane points' RMS distance) of the plane are removed [mm]
  double min_removal_band_mm = 2.0;
  /// near the object's footprint, only points within max(this, 4 × the RMS) [mm]
  double min_contact_band_mm = 0.5;
  /// the footprint: the convex hull of the object's points from the removal band to this much
  /// above it [mm]
  double foot_height_mm = 5.0;
  /// a point of the object in the removal band projects within this of its footprint [mm]
  double footprint_margin_mm = 3.0;
};

struct SupportPlane {
  bool found = false;
  pipeline::Kernel::Plane_3 plane;  ///< oriented towards the object
  std::size_t points_removed = 0;
  double beyond_share = 0;    ///< share of the plane's sample points beyond the object's outline
  double width_mm = 0;        ///< largest extent of the plane's sample points
  double outline_width_mm = 0;  ///< the object's outline on the plane: its larger side [mm]
  double removal_band_mm = 0;
  double contact_band_mm = 0;
  double footprint_margin_mm = 0;
  /// where the object stands on the plane (in-plane coordinates in mm, orthonormal): a convex
  /// polygon, counterclockwise;
  /// empty when the object does not reach down to the plane
  std::vector<pipeline::Kernel::Point_2> footprint;
  /// p belongs to the support: beyond the plane, within the contact band, or within the removal
  /// band and more than footprint_margin_mm outside the footprint
  bool holds(const pipeline::Point& p) const;
  /// The log line of its removal: "removed <count> <what> of a plane the object stood on (...)".
  std::string removal_line(std::size_t count, const std::string& what) const;
};

/// Distance of q outside the convex polygon `hull` (counterclockwise) [mm], 0 inside it.
double distance_outside_convex_polygon(const pipeline::Kernel::Point_2& q,
                                       const std::vector<pipeline::Kernel::Point_2>& hull);

/// Finds the support the object stood on, if the points hold one.
///
/// @param[in] points  points [mm], a scan's or a mesh's vertices
/// @param[in] opt     SupportPlaneOptions
/// @return what was found (points_removed 0)
/// The same points give the same result in every run; CGAL::get_default_random() is left as it was.
SupportPlane find_support_plane(const std::vector<pipeline::Point>& points, const SupportPlaneOptions& opt = {});

/// find_support_plane, then removes the points it holds.
///
/// @param[in,out] pn  points [mm] (normals unused, kept with their points); on return without
///                    the support's points, in their order
/// @return what was found; found == false leaves pn as it was
SupportPlane remove_support_plane(std::vector<std::pair<pipeline::Point, pipeline::Vector>>& pn,
                                  const SupportPlaneOptions& opt = {});

}  // namespace scan2cad
