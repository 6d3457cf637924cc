// Jet refit of oriented points over neighbourhoods on their own side; see refit_on_own_side.h.
#include "scan2cad/internal/refit_on_own_side.h"

#include <CGAL/Monge_via_jet_fitting.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "scan2cad/internal/point_set_steps.h"

namespace scan2cad::internal {

namespace {
using PN = std::pair<pipeline::Point, pipeline::Vector>;
}  // namespace

RefitStats refit_on_own_side(std::vector<PN>& pn, std::vector<pipeline::Point>& raw, unsigned k, double min_cos,
                             std::vector<char>* thin) {
  RefitStats st;
  const std::size_t n = pn.size();
  if (raw.size() != n) throw std::invalid_argument("refit_on_own_side: one unsmoothed position per point expected");
  if (thin) thin->assign(n, 0);
  if (n <= k) return st;
  std::vector<PN> raw_oriented(n);
  for (std::size_t i = 0; i < n; ++i) raw_oriented[i] = {raw[i], pn[i].second};
  std::vector<PN> fitted = pn;
  std::vector<double> move(n, -1.0);  // -1: too few on its side, -2: no other side in reach
  const unsigned candidates = 2 * k, least = std::max(6u, k / 2);
  {
    const PointNeighborQuery query(raw_oriented, PointWithNormalPointMap());
#pragma omp parallel for schedule(static)
    for (long li = 0; li < long(n); ++li) {
      const std::size_t i = std::size_t(li);
      std::vector<std::vector<PN>::const_iterator> near;
      query.get_iterators(raw[i], k, 0, std::back_inserter(near));
      const pipeline::Vector& ni = pn[i].second;
      // the other side among the k nearest, as the smoothing saw them (most points: none)
      if (std::none_of(near.begin(), near.end(), [&](const auto& it) { return it->second * ni < 0; })) {
        move[i] = -2;
        continue;
      }
      near.clear();
      query.get_iterators(raw[i], candidates, 0, std::back_inserter(near));
      // the fit's origin is its range's first point: the point itself
      std::vector<pipeline::Point> own{raw[i]};
      for (const auto& it : near) {
        if (own.size() == k) break;
        if (std::size_t(it - raw_oriented.begin()) == i || it->second * ni <= min_cos) continue;
        own.push_back(it->first);
      }
      if (own.size() < least) continue;
      CGAL::Monge_via_jet_fitting<pipeline::Kernel> fit;
      const auto form = fit(own.begin(), own.end(), jet_degree_fitting, jet_degree_monge);
      const pipeline::Vector normal = form.normal_direction();
      fitted[i] = {form.origin(), normal * ni < 0 ? -normal : normal};
      move[i] = std::sqrt(CGAL::squared_distance(raw[i], form.origin()));
    }
  }
  std::vector<double> moves;
  for (double m : move)
    if (m >= 0) moves.push_back(m);
  const double limit = spike_move_limit_mm(std::move(moves));
  std::vector<PN> kept;
  kept.reserve(n);
  std::vector<pipeline::Point> raw_kept;
  raw_kept.reserve(n);
  if (thin) thin->clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (move[i] > limit) {
      ++st.spikes;
      continue;
    }
    raw_kept.push_back(raw[i]);
    if (move[i] == -2.0) {
      ++st.one_sided;
      kept.push_back(pn[i]);
    } else if (move[i] < 0) {
      ++st.too_few;
      kept.push_back(pn[i]);
    } else {
      ++st.refitted;
      kept.push_back(fitted[i]);
    }
    if (thin) thin->push_back(move[i] != -2.0);
  }
  pn.swap(kept);
  raw.swap(raw_kept);
  return st;
}

}  // namespace scan2cad::internal
