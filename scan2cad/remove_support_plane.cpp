// The support a scanned object stood on, found and removed; see remove_support_plane.h.
#include "scan2cad/remove_support_plane.h"

#include <CGAL/Polygon_2.h>
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
  s.removal_band_mm = std::max(opt.min_removal_band_mm, 4.0 * std::sqrt(sum_sq / double(plane_points.size())));

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
    if (!is_plane[i] && signed_mm(sample[i].first) > s.removal_band_mm) outline_points.push_back(plane.to_2d(sample[i].first));
  std::vector<Point2> hull;
  CGAL::convex_hull_2(outline_points.begin(), outline_points.end(), std::back_inserter(hull));
  if (hull.size() < 3) return s;  // the rest on a line: no outline to be beyond (and no polygon)
  const CGAL::Polygon_2<pipeline::Kernel> outline(hull.begin(), hull.end());
  std::size_t beyond = 0;
  for (const Point& p : plane_points) {
    const Point2 q = plane.to_2d(p);
    if (outline.bounded_side(q) != CGAL::ON_UNBOUNDED_SIDE) continue;
    double nearest_sq = std::numeric_limits<double>::infinity();
    for (auto e = outline.edges_begin(); e != outline.edges_end(); ++e)
      nearest_sq = std::min(nearest_sq, CGAL::to_double(CGAL::squared_distance(q, *e)));
    beyond += nearest_sq > opt.outline_gap_mm * opt.outline_gap_mm;
  }
  s.beyond_share = double(beyond) / double(plane_points.size());
  s.width_mm = pipeline::largest_extent(plane_points);
  s.found = s.beyond_share >= opt.min_beyond_share;
  return s;
}

}  // namespace

bool SupportPlane::holds(const Point& p) const {
  return found && signed_distance_mm(plane, p) <= removal_band_mm;
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
