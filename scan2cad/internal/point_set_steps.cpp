// CGAL's per-point point-set steps on all OpenMP threads; see point_set_steps.h.
#include "scan2cad/internal/point_set_steps.h"

#include <CGAL/Eigen_svd.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/jet_smooth_point_set.h>
#include <CGAL/linear_least_squares_fitting_3.h>
#include <CGAL/property_map.h>
#include <CGAL/remove_outliers.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

namespace scan2cad::internal {

namespace {

// f(i) for every point index, the same indices on the same thread in every run (static schedule)
template <class PerPoint>
void for_each_point(std::size_t n, const PerPoint& f) {
#pragma omp parallel for schedule(static)
  for (long i = 0; i < long(n); ++i) f(std::size_t(i));
}

}  // namespace

double average_spacing(const std::vector<PointWithNormal>& pn, unsigned k) {
  const PointNeighborQuery query(pn, PointWithNormalPointMap());
  std::vector<double> spacing(pn.size());
  for_each_point(pn.size(), [&](std::size_t i) {
    spacing[i] = CGAL::internal::compute_average_spacing<PointNeighborQuery>(pn[i].first, query, k);
  });
  double sum = 0;  // in point order, as CGAL's sequential sum
  for (double s : spacing) sum += s;
  return pn.empty() ? 0.0 : sum / double(pn.size());
}

namespace {

// CGAL's remove_outliers partition of (score, point) pairs: the points scored below t2 are kept,
// in the order std::partition leaves them (not stable), as CGAL leaves them.
std::size_t keep_below(std::vector<std::pair<double, PointWithNormal>>& scored, double t2,
                       std::vector<PointWithNormal>& pn) {
  const auto end_kept =
      std::partition(scored.begin(), scored.end(), [t2](const std::pair<double, PointWithNormal>& p) { return p.first < t2; });
  const std::size_t removed = std::size_t(scored.end() - end_kept);
  pn.clear();
  for (auto it = scored.begin(); it != end_kept; ++it) pn.push_back(it->second);
  return removed;
}

}  // namespace

std::size_t remove_far_points(std::vector<PointWithNormal>& pn, unsigned k, double threshold_distance_mm) {
  std::vector<std::pair<double, PointWithNormal>> scored(pn.size());
  {
    PointNeighborQuery query(pn, PointWithNormalPointMap());
    for_each_point(pn.size(), [&](std::size_t i) {
      scored[i] = {CGAL::internal::compute_avg_knn_sq_distance_3(pn[i].first, query, k, 0.0), pn[i]};
    });
  }
  return keep_below(scored, threshold_distance_mm * threshold_distance_mm, pn);
}

std::size_t remove_points_beyond_spacing(std::vector<PointWithNormal>& pn, unsigned k, double factor) {
  if (pn.empty()) return 0;
  std::vector<std::pair<double, PointWithNormal>> scored(pn.size());
  std::vector<double> spacing(pn.size());
  {
    PointNeighborQuery query(pn, PointWithNormalPointMap());
    for_each_point(pn.size(), [&](std::size_t i) {
      // the sums of CGAL::internal::compute_average_spacing and compute_avg_knn_sq_distance_3,
      // over the one neighbour list both would fetch
      std::vector<pipeline::Point> neighbors;
      query.get_points(pn[i].first, k, 0, std::back_inserter(neighbors));
      double sum_distances = 0, sum_squared = 0;
      for (const pipeline::Point& p : neighbors) {
        const double d2 = CGAL::squared_distance(pn[i].first, p);
        sum_distances += CGAL::approximate_sqrt(d2);
        sum_squared += d2;
      }
      spacing[i] = sum_distances / double(neighbors.size());
      scored[i] = {sum_squared / double(neighbors.size()), pn[i]};
    });
  }
  double sum = 0;  // in point order, as average_spacing
  for (double s : spacing) sum += s;
  const double threshold_mm = factor * (sum / double(pn.size()));
  return keep_below(scored, threshold_mm * threshold_mm, pn);
}

void jet_smooth(std::vector<PointWithNormal>& pn, unsigned k) {
  std::vector<pipeline::Point> smoothed(pn.size());
  {
    const PointNeighborQuery query(pn, PointWithNormalPointMap());
    for_each_point(pn.size(), [&](std::size_t i) {
      smoothed[i] =
          CGAL::internal::jet_smooth_point<CGAL::Eigen_svd>(pn[i].first, query, k, 0.0, jet_degree_fitting, jet_degree_monge);
    });
  }
  for (std::size_t i = 0; i < pn.size(); ++i) pn[i].first = smoothed[i];
}

void jet_normals(std::vector<PointWithNormal>& pn, unsigned k) {
  std::vector<pipeline::Vector> normal(pn.size());
  {
    const PointNeighborQuery query(pn, PointWithNormalPointMap());
    for_each_point(pn.size(), [&](std::size_t i) {
      normal[i] = CGAL::internal::jet_estimate_normal<CGAL::Eigen_svd>(pn[i].first, query, k, 0.0, jet_degree_fitting);
    });
  }
  for (std::size_t i = 0; i < pn.size(); ++i) pn[i].second = normal[i];
}

namespace {

// The share of up to `samples` evenly spread points of pn (every stride-th) for which
// passes(i, query) holds; 1 for no points. query: CGAL's k-nearest query over all of pn.
template <class Test>
double share_of_spread_points(const std::vector<PointWithNormal>& pn, std::size_t samples, const Test& passes) {
  if (pn.empty() || samples == 0) return 1.0;
  const std::size_t stride = (pn.size() + samples - 1) / samples;  // at most `samples` points
  const PointNeighborQuery query(pn, PointWithNormalPointMap());
  std::size_t tested = 0, passed = 0;
  for (std::size_t i = 0; i < pn.size(); i += stride, ++tested) passed += passes(i, query);
  return double(passed) / double(tested);
}

}  // namespace

double share_of_normals_along_surface(const std::vector<PointWithNormal>& pn, unsigned k, std::size_t samples) {
  return share_of_spread_points(pn, samples, [&](std::size_t i, const PointNeighborQuery& query) {
    const pipeline::Vector jet =
        CGAL::internal::jet_estimate_normal<CGAL::Eigen_svd>(pn[i].first, query, k, 0.0, jet_degree_fitting);
    const double scale = std::sqrt(jet.squared_length() * pn[i].second.squared_length());
    return scale > 0 && std::abs(jet * pn[i].second) >= std::cos(M_PI / 4) * scale;
  });
}

double share_of_points_on_a_surface(const std::vector<PointWithNormal>& pn, unsigned k, std::size_t samples,
                                    double min_quality) {
  std::vector<pipeline::Point> neighbours;
  return share_of_spread_points(pn, samples, [&](std::size_t i, const PointNeighborQuery& query) {
    neighbours.clear();
    query.get_points(pn[i].first, k, 0.0, std::back_inserter(neighbours));
    pipeline::Kernel::Plane_3 plane;
    pipeline::Point centroid;
    return CGAL::linear_least_squares_fitting_3(neighbours.begin(), neighbours.end(), plane, centroid,
                                                CGAL::Dimension_tag<0>()) >= min_quality;
  });
}

double spike_move_limit_mm(std::vector<double> moves_mm) {
  if (moves_mm.empty()) return std::numeric_limits<double>::infinity();
  const auto middle = moves_mm.begin() + long(moves_mm.size() / 2);
  std::nth_element(moves_mm.begin(), middle, moves_mm.end());
  return std::max(4.0 * 1.4826 * *middle, min_spike_move_mm);
}

}  // namespace scan2cad::internal
