// The support a scanned object stood on, found and removed; see remove_support_plane.h.
#include "scan2cad/remove_support_plane.h"

#include <CGAL/Bbox_2.h>
#include <CGAL/Random.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/Shape_detection/Efficient_RANSAC.h>
#include <CGAL/linear_least_squares_fitting_3.h>
#include <CGAL/pca_estimate_normals.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include "pipeline/units.h"
#include "scan2cad/internal/point_set_steps.h"

namespace scan2cad {

namespace {

using pipeline::Point;
using pipeline::Vector;
using PN = std::pair<Point, Vector>;
using Plane = pipeline::Kernel::Plane_3;
using Point2 = pipeline::Kernel::Point_2;
using PointMap = CGAL::First_of_pair_property_map<PN>;
using NormalMap = CGAL::Second_of_pair_property_map<PN>;
using Traits = CGAL::Shape_detection::Efficient_RANSAC_traits<pipeline::Kernel, std::vector<PN>, PointMap, NormalMap>;
using Ransac = CGAL::Shape_detection::Efficient_RANSAC<Traits>;
using RansacPlane = CGAL::Shape_detection::Plane<Traits>;

// Signed distance of p from the plane [mm], positive on the side its normal points to.
double signed_distance_mm(const Plane& plane, const Point& p) {
  return CGAL::to_double(plane.a() * p.x() + plane.b() * p.y() + plane.c() * p.z() + plane.d()) /
         std::sqrt(CGAL::to_double(plane.orthogonal_vector().squared_length()));
}

// Coordinates of p in the plane [mm]. Not Plane_3::to_2d: CGAL's base1 and base2 are not unit
// vectors (0.82-1 times the normal's length), so outline_gap_mm and footprint_margin_mm came out
// up to 18 % tighter and outline_width_mm up to 22 % wider than stated on a tilted table (sweep S).
Point2 in_plane_mm(const Plane& plane, const Point& p) {
  const pipeline::Vector n = plane.orthogonal_vector() / std::sqrt(CGAL::to_double(plane.orthogonal_vector().squared_length()));
  pipeline::Vector u = plane.base1();
  u = u / std::sqrt(CGAL::to_double(u.squared_length()));
  const pipeline::Vector v = CGAL::cross_product(n, u), d = p - plane.point();
  return {CGAL::to_double(d * u), CGAL::to_double(d * v)};
}

// Judges one detected plane against the sample; found == false when it is no support.
SupportPlane judge(const std::vector<PN>& sample, const std::vector<std::size_t>& on_plane, const Plane& detected,
                   const SupportPlaneOptions& opt) {
  SupportPlane s;
  // refit on the plane's points (RANSAC's plane passes through three of them)
  std::vector<Point> plane_points;
  for (std::size_t i : on_plane) plane_points.push_back(sample[i].first);
  Plane plane = detected;
  Point centroid;
  CGAL::linear_least_squares_fitting_3(plane_points.begin(), plane_points.end(), plane, centroid,
                                       CGAL::Dimension_tag<0>());
  const auto signed_mm = [&](const Point& p) { return signed_distance_mm(plane, p); };  // plane as oriented below
  double sum_sq = 0;
  for (const Point& p : plane_points) sum_sq += signed_mm(p) * signed_mm(p);
  const double rms_mm = std::sqrt(sum_sq / double(plane_points.size()));
  s.removal_band_mm = std::max(opt.min_removal_band_mm, 4.0 * rms_mm);
  s.contact_band_mm = std::min(s.removal_band_mm, std::max(opt.min_contact_band_mm, 4.0 * rms_mm));
  s.footprint_margin_mm = opt.footprint_margin_mm;

  // 1. the object on one side
  std::vector<char> is_plane(sample.size(), 0);
  for (std::size_t i : on_plane) is_plane[i] = 1;
  std::size_t above = 0, below = 0;
  for (std::size_t i = 0; i < sample.size(); ++i) {
    if (is_plane[i]) continue;
    const double d = signed_mm(sample[i].first);
    above += d > s.removal_band_mm;
    below += d < -s.removal_band_mm;
  }
  // a plane with nearly nothing off it is the object itself (a flat patch, refused later)
  if (above + below < on_plane.size() / 4 + 1) return s;
  if (below > above) {
    plane = plane.opposite();
    std::swap(above, below);
  }
  if (double(below) > opt.max_other_side_share * double(above + below)) return s;
  s.plane = plane;

  // 2. beyond the object's outline: its other points projected onto the plane, their convex
  //    hull. Not their nearest projected point: a generated cup's flat part has no point of the
  //    cup above or below it (its inner sheet lies within the band), yet lies inside its outline.
  std::vector<Point2> outline_points;
  for (std::size_t i = 0; i < sample.size(); ++i)
    if (!is_plane[i] && signed_mm(sample[i].first) > s.removal_band_mm) outline_points.push_back(in_plane_mm(plane, sample[i].first));
  std::vector<Point2> outline;
  CGAL::convex_hull_2(outline_points.begin(), outline_points.end(), std::back_inserter(outline));
  if (outline.size() < 3) return s;  // the rest on a line: no outline to be beyond
  std::size_t beyond = 0;
  for (const Point& p : plane_points) beyond += distance_outside_convex_polygon(in_plane_mm(plane, p), outline) > opt.outline_gap_mm;

  // where the object stands on the plane, if it does
  std::vector<Point2> foot_points;
  for (std::size_t i = 0; i < sample.size(); ++i) {
    const double d = signed_mm(sample[i].first);
    if (!is_plane[i] && d > s.removal_band_mm && d <= s.removal_band_mm + opt.foot_height_mm)
      foot_points.push_back(in_plane_mm(plane, sample[i].first));
  }
  CGAL::convex_hull_2(foot_points.begin(), foot_points.end(), std::back_inserter(s.footprint));
  s.beyond_share = double(beyond) / double(plane_points.size());
  s.width_mm = pipeline::largest_extent(plane_points);
  // 3. as wide as the object: a table reaches out on every side of what stands on it. A cup with
  //    two 30-40 mm scan holes had a 58 mm patch of its side (27 % "beyond" it, past a hole)
  //    taken for a table, and repair cut away a quarter of the cup (sweep K); tables measured
  //    280 mm under NIOSH medium, whose outline on them is about 200 mm.
  auto extent_2d = [](const std::vector<Point2>& q) {
    const auto box = CGAL::bbox_2(q.begin(), q.end());
    return std::max(box.xmax() - box.xmin(), box.ymax() - box.ymin());
  };
  std::vector<Point2> plane_2d;
  for (const Point& p : plane_points) plane_2d.push_back(in_plane_mm(plane, p));
  s.outline_width_mm = extent_2d(outline);
  s.found = s.beyond_share >= opt.min_beyond_share && extent_2d(plane_2d) >= opt.min_outline_width_share * s.outline_width_mm;
  return s;
}

}  // namespace

double distance_outside_convex_polygon(const Point2& q, const std::vector<Point2>& hull) {
  if (hull.empty()) return std::numeric_limits<double>::infinity();
  // q is inside when it is on no edge's right (a single point or a segment has no inside)
  double nearest_sq = std::numeric_limits<double>::infinity();
  bool inside = hull.size() >= 3;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Point2& a = hull[i];
    const Point2& b = hull[(i + 1) % hull.size()];
    inside = inside && CGAL::orientation(a, b, q) != CGAL::RIGHT_TURN;
    nearest_sq = std::min(nearest_sq, a == b ? CGAL::to_double(CGAL::squared_distance(q, a))
                                             : CGAL::to_double(CGAL::squared_distance(q, pipeline::Kernel::Segment_2(a, b))));
  }
  return inside ? 0.0 : std::sqrt(nearest_sq);
}

std::string SupportPlane::removal_line(std::size_t count, const std::string& what) const {
  return "  removed " + std::to_string(count) + " " + what + " of a plane the object stood on (a table or turntable, " +
         pipeline::format_number(width_mm) + " mm across, " + std::to_string(int(std::lround(100 * beyond_share))) +
         " % of it beyond the object; --keep-support keeps it)";
}

bool SupportPlane::holds(const Point& p) const {
  if (!found) return false;
  const double d = signed_distance_mm(plane, p);
  if (d <= contact_band_mm) return true;
  return d <= removal_band_mm && distance_outside_convex_polygon(in_plane_mm(plane, p), footprint) > footprint_margin_mm;
}

SupportPlane find_support_plane(const std::vector<Point>& points, const SupportPlaneOptions& opt) {
  if (points.size() < 100) return {};
  // Why a subsample: the RANSAC and its normals cost in proportion to the points, and a table
  // holds thousands of them in any scan that shows it.
  std::vector<PN> sample;
  const std::size_t stride = (points.size() + opt.sample_points - 1) / opt.sample_points;
  for (std::size_t i = 0; i < points.size(); i += stride) sample.push_back({points[i], Vector(0, 0, 0)});
  CGAL::pca_estimate_normals<CGAL::Sequential_tag>(sample, 12,
                                                   CGAL::parameters::point_map(PointMap()).normal_map(NormalMap()));
  const double spacing_mm = internal::average_spacing(sample, 6);

  Ransac ransac;
  ransac.set_input(sample);
  ransac.add_shape_factory<RansacPlane>();
  Ransac::Parameters parameters;
  parameters.probability = 0.01;
  parameters.min_points = std::max<std::size_t>(50, std::size_t(opt.min_plane_share * double(sample.size())));
  parameters.epsilon = opt.ransac_epsilon_mm;
  parameters.cluster_epsilon = 3.0 * spacing_mm;  // the plane's points one connected patch
  parameters.normal_threshold = 0.9;              // within 25 deg of the plane's normal
  // The RANSAC draws from CGAL's default generator, which Poisson uses after it: drawn from a
  // generator of its own, so the search is the same in every run and the rest of reconstruct
  // gives the same mesh as without it when no support is found.
  const CGAL::Random caller_random = CGAL::get_default_random();
  CGAL::get_default_random() = CGAL::Random(20261206);
  ransac.detect(parameters);
  CGAL::get_default_random() = caller_random;

  // the largest plane that is a support
  std::vector<std::pair<std::size_t, const RansacPlane*>> planes;
  for (const auto& shape : ransac.shapes())
    if (const auto* plane = dynamic_cast<const RansacPlane*>(shape.get()))
      planes.push_back({plane->indices_of_assigned_points().size(), plane});
  std::stable_sort(planes.begin(), planes.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [size, plane] : planes) {
    const SupportPlane s = judge(sample, plane->indices_of_assigned_points(), Plane(*plane), opt);
    if (s.found) return s;
  }
  return {};
}

SupportPlane remove_support_plane(std::vector<PN>& pn, const SupportPlaneOptions& opt) {
  std::vector<Point> points(pn.size());
  std::transform(pn.begin(), pn.end(), points.begin(), [](const PN& p) { return p.first; });
  SupportPlane s = find_support_plane(points, opt);
  if (!s.found) return s;
  const std::size_t before = pn.size();
  pn.erase(std::remove_if(pn.begin(), pn.end(), [&](const PN& p) { return s.holds(p.first); }), pn.end());
  s.points_removed = before - pn.size();
  return s;
}

}  // namespace scan2cad
