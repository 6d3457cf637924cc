#include "solve/internal/contact_geometry.h"

#include <algorithm>
#include <cmath>

namespace solve::internal {

namespace {
inline double dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

ClosestPoint make(const double* p, const double* a, const double* b, const double* c, double wa,
                  double wb, double wc, Feature f) {
  ClosestPoint r;
  r.weight = {wa, wb, wc};
  r.feature = f;
  r.dist2 = 0;
  for (int k = 0; k < 3; ++k) {
    r.point[k] = wa * a[k] + wb * b[k] + wc * c[k];
    const double d = p[k] - r.point[k];
    r.dist2 += d * d;
  }
  return r;
}
}  // namespace

ClosestPoint closest_point_on_triangle(const double* p, const double* a, const double* b,
                                       const double* c) {
  double ab[3], ac[3], ap[3], bp[3], cp[3];
  for (int k = 0; k < 3; ++k) {
    ab[k] = b[k] - a[k];
    ac[k] = c[k] - a[k];
    ap[k] = p[k] - a[k];
    bp[k] = p[k] - b[k];
    cp[k] = p[k] - c[k];
  }
  // Voronoi regions tested in Ericson's order: vertex a, vertex b, edge ab, vertex c, edge ca,
  // edge bc, face. Ties on region boundaries give the same closest point either way.
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return make(p, a, b, c, 1, 0, 0, Feature::vertex0);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return make(p, a, b, c, 0, 1, 0, Feature::vertex1);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double den = d1 - d3;
    const double t = den > 0 ? d1 / den : 0;
    return make(p, a, b, c, 1 - t, t, 0, Feature::edge0);
  }
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return make(p, a, b, c, 0, 0, 1, Feature::vertex2);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double den = d2 - d6;
    const double t = den > 0 ? d2 / den : 0;
    return make(p, a, b, c, 1 - t, 0, t, Feature::edge2);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double den = (d4 - d3) + (d5 - d6);
    const double t = den > 0 ? (d4 - d3) / den : 0;
    return make(p, a, b, c, 0, 1 - t, t, Feature::edge1);
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) return make(p, a, b, c, 1, 0, 0, Feature::vertex0);  // degenerate triangle
  const double v = vb / sum, w = vc / sum;
  return make(p, a, b, c, 1 - v - w, v, w, Feature::face);
}

void BoxGrid::build(const std::vector<std::array<double, 6>>& boxes, double cell_factor) {
  start.clear();
  items.clear();
  n = {0, 0, 0};
  if (boxes.empty()) return;
  std::array<double, 3> hi;
  double extent = 0;
  for (int k = 0; k < 3; ++k) {
    lo[k] = boxes[0][k];
    hi[k] = boxes[0][k + 3];
  }
  for (const auto& b : boxes) {
    double e = 0;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], b[k]);
      hi[k] = std::max(hi[k], b[k + 3]);
      e = std::max(e, b[k + 3] - b[k]);
    }
    extent += e;
  }
  const double span = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-12});
  cell = std::max(cell_factor * extent / double(boxes.size()), 1e-9 * span);
  const double max_cells = 8.0 * double(boxes.size()) + 64;
  for (;;) {
    double total = 1;
    for (int k = 0; k < 3; ++k) total *= std::floor((hi[k] - lo[k]) / cell) + 1;
    if (total <= max_cells) break;
    cell *= 1.26;
  }
  for (int k = 0; k < 3; ++k) n[k] = long(std::floor((hi[k] - lo[k]) / cell)) + 1;
  const long n_cells = n[0] * n[1] * n[2];
  auto index = [&](double v, int k) {
    return std::clamp(long(std::floor((v - lo[k]) / cell)), 0L, n[k] - 1);
  };
  // Counting sort: count, prefix sum, fill in box order (ids ascend within each cell).
  std::vector<std::array<long, 6>> range(boxes.size());
  start.assign(std::size_t(n_cells) + 1, 0);
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    auto& r = range[i];
    for (int k = 0; k < 3; ++k) {
      r[k] = index(boxes[i][k], k);
      r[k + 3] = index(boxes[i][k + 3], k);
    }
    for (long z = r[2]; z <= r[5]; ++z)
      for (long y = r[1]; y <= r[4]; ++y)
        for (long x = r[0]; x <= r[3]; ++x) ++start[std::size_t((z * n[1] + y) * n[0] + x + 1)];
  }
  for (long c = 0; c < n_cells; ++c) start[std::size_t(c + 1)] += start[std::size_t(c)];
  items.resize(std::size_t(start.back()));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const auto& r = range[i];
    for (long z = r[2]; z <= r[5]; ++z)
      for (long y = r[1]; y <= r[4]; ++y)
        for (long x = r[0]; x <= r[3]; ++x)
          items[std::size_t(fill[std::size_t((z * n[1] + y) * n[0] + x)]++)] = int(i);
  }
}

long BoxGrid::cell_of(const double* p) const {
  if (start.empty()) return -1;
  long id[3];
  for (int k = 0; k < 3; ++k) {
    const double f = std::floor((p[k] - lo[k]) / cell);
    if (!(f >= 0) || f >= double(n[k])) return -1;  // outside, or NaN
    id[k] = long(f);
  }
  return (id[2] * n[1] + id[1]) * n[0] + id[0];
}

}  // namespace solve::internal
