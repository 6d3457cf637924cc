#include "data/generator/head_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"

namespace generator {

namespace {

// Approximate signed distances (Quilez) and a polynomial smooth minimum: the design below is a
// smooth union of simple parts; blending radii k are in mm.
double ellipsoid(const Point& p, double cx, double cy, double cz, double rx, double ry, double rz) {
  const double x = p.x() - cx, y = p.y() - cy, z = p.z() - cz;
  const double k0 = std::sqrt(x * x / (rx * rx) + y * y / (ry * ry) + z * z / (rz * rz));
  const double k1 = std::sqrt(x * x / (rx * rx * rx * rx) + y * y / (ry * ry * ry * ry) + z * z / (rz * rz * rz * rz));
  return k1 > 1e-12 ? k0 * (k0 - 1.0) / k1 : -std::min({rx, ry, rz});
}
double smin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}
double smax(double a, double b, double k) { return -smin(-a, -b, k); }

// Culling (speed only, bit-identical values): smin(f, b, k) returns f exactly, f - 0.0, when
// b - f >= k (then h = 0), and smax(f, -b, k) returns f exactly when b + f >= k. So a part
// whose value is certainly that far above need not be evaluated. The bounds below are proven
// from the formulas, and kCullSlack (1e-3 mm, ~1e9 times the rounding error of values of a
// few hundred mm) makes them hold for the computed values too; the output is byte-identical.
constexpr double kCullSlack = 1e-3;

/// True if ellipsoid(p, c, r) > t for certain. With u = p − c, k0 = |u/r| ≥ |u|/r_max and
/// k1 = |u/r²| ≤ k0/r_min, so for k0 > 1: k0(k0 − 1)/k1 ≥ (k0 − 1)·r_min ≥ (|u|/r_max − 1)·r_min,
/// which exceeds max(t, 0) when |u| > r_max·(1 + max(t, 0)/r_min).
inline bool ellipsoid_above(const Point& p, double cx, double cy, double cz, double rx, double ry, double rz,
                            double t) {
  const double x = p.x() - cx, y = p.y() - cy, z = p.z() - cz;
  const double r_min = std::min({rx, ry, rz}), r_max = std::max({rx, ry, rz});
  const double reach = r_max * (1.0 + (std::max(t, 0.0) + kCullSlack) / r_min);
  return x * x + y * y + z * z > reach * reach;
}
/// smin(f, ellipsoid(p, ..), k), skipping the ellipsoid where it cannot change f.
inline double smin_ellipsoid(double f, const Point& p, double cx, double cy, double cz, double rx, double ry,
                             double rz, double k) {
  if (ellipsoid_above(p, cx, cy, cz, rx, ry, rz, f + k)) return f;
  return smin(f, ellipsoid(p, cx, cy, cz, rx, ry, rz), k);
}
/// Capsule from a to b whose radius goes linearly from ra to rb.
double tapered_capsule(const Point& p, const Point& a, const Point& b, double ra, double rb) {
  const Vector ab = b - a;
  const double t = std::clamp((p - a) * ab / ab.squared_length(), 0.0, 1.0);
  return std::sqrt(CGAL::squared_distance(p, a + t * ab)) - (ra + t * (rb - ra));
}
double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

constexpr double kSellionY = 22.0;  // sellion height of the base design [mm]
constexpr double kNeckCutY = -160.0;

struct Range {
  const char* name;
  double HeadParams::*field;
  double lo, hi;
};
const std::array<Range, 8> kFields{{{"face_length", &HeadParams::face_length, 80, 170},
                                    {"face_width", &HeadParams::face_width, 100, 190},
                                    {"jaw_width", &HeadParams::jaw_width, 70, 160},
                                    {"head_breadth", &HeadParams::head_breadth, 110, 200},
                                    {"head_length", &HeadParams::head_length, 150, 240},
                                    {"head_height", &HeadParams::head_height, 70, 150},
                                    {"nose_protrusion", &HeadParams::nose_protrusion, 8, 35},
                                    {"nose_breadth", &HeadParams::nose_breadth, 20, 50}}};

}  // namespace

HeadParams read_head_params(const std::string& path, const std::string& id) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(pipeline::read_text(path));
  } catch (const nlohmann::json::exception& e) {
    throw pipeline::bad_input(path, std::string("not valid JSON: ") + e.what());
  }
  if (!j.contains("headforms") || !j["headforms"].is_object())
    throw pipeline::bad_input(path, "no \"headforms\" object");
  if (!j["headforms"].contains(id)) {
    std::string known;
    for (auto it = j["headforms"].begin(); it != j["headforms"].end(); ++it) known += " " + it.key();
    throw pipeline::bad_input(path, "unknown headform id '" + id + "', known:" + known);
  }
  const auto& h = j["headforms"][id];
  HeadParams p;
  for (const Range& r : kFields) {
    if (!h.contains(r.name) || !h[r.name].is_number())
      throw pipeline::bad_input(path, "headform '" + id + "': missing number \"" + r.name + "\"");
    const double v = h[r.name].get<double>();
    if (!(v >= r.lo && v <= r.hi))
      throw pipeline::bad_input(path, "headform '" + id + "': " + r.name + " = " + std::to_string(v) +
                                          " mm, expected " + std::to_string(int(r.lo)) + ".." +
                                          std::to_string(int(r.hi)));
    p.*(r.field) = v;
  }
  return p;
}

double HeadShape::base_value(const Point& q) const {
  const double x = q.x(), ax = std::abs(x), y = q.y(), z = q.z();
  const Point m(ax, y, z);  // mirrored: paired parts are written for the +x side only
  // Cranium and occiput.
  double f = ellipsoid(q, 0, 30, 2, 76, 95, 97);
  f = smin_ellipsoid(f, q, 0, 20, -42, 71, 78, 55, 10);
  f = smin_ellipsoid(f, q, 0, 45, 40, 66, 55, 60, 12);  // broad, flat forehead
  // Brow ridge, forehead-to-nose.
  f = smin_ellipsoid(f, q, 0, 34, 82, 56, 12, 18, 8);
  // Mid-face (maxilla), cheekbones and zygomatic arches.
  f = smin_ellipsoid(f, q, 0, -28, 28, 72, 60, 68, 10);
  f = smin_ellipsoid(f, m, 44, 2, 52, 22, 16, 26, 10);
  f = smin_ellipsoid(f, m, 63, 3, 14, 11, 10, 42, 8);
  // Mandible: body, angles (gonion), chin, lips.
  f = smin_ellipsoid(f, q, 0, -70, 36, 52, 30, 58, 12);
  f = smin_ellipsoid(f, m, 48, -66, -4, 12, 22, 18, 10);
  f = smin_ellipsoid(f, q, 0, -86, 74, 22, 13, 16, 12);
  f = smin_ellipsoid(f, q, 0, -46, 90, 20, 10, 12, 10);
  f = smin_ellipsoid(f, q, 0, -62, 88, 18, 9, 11, 10);
  // Nose: bridge from the sellion to the tip, tip, alae. Scaled in depth and breadth.
  {
    const double zb = 90.0;  // nose base depth: protrusion is scaled from here
    const Point qn(x / s_nb_, y, zb + (z - zb) / s_np_);
    const Point qn_mirrored(std::abs(qn.x()), qn.y(), qn.z());
    const Point bridge_top(0, 18, 92), bridge_tip(0, -14, 104);
    const double nose_scale = std::min(s_nb_, s_np_);  // > 0
    // Culling the whole nose: n ≥ min(capsule, tip, alae) − 6/4 − 5/4 (each smin lowers the
    // minimum by at most k/4), so f is unchanged when all three exceed t_nose. The capsule is
    // at least its distance to the segment's midpoint minus half its length and its largest
    // radius (8 mm).
    const double t_nose = std::max((f + 5 + kCullSlack) / nose_scale + 2.75, 0.0);
    const double capsule_reach = 0.5 * std::sqrt((bridge_tip - bridge_top).squared_length()) + 8.0 + t_nose + kCullSlack;
    const bool nose_far = (qn - CGAL::midpoint(bridge_top, bridge_tip)).squared_length() > capsule_reach * capsule_reach &&
                          ellipsoid_above(qn, 0, -18, 107, 10, 9, 10, t_nose) &&
                          ellipsoid_above(qn_mirrored, 12, -26, 99, 8, 7, 8, t_nose);
    if (!nose_far) {
      double n = tapered_capsule(qn, bridge_top, bridge_tip, 5.5, 8.0);
      n = smin(n, ellipsoid(qn, 0, -18, 107, 10, 9, 10), 6);
      n = smin(n, ellipsoid(qn_mirrored, 12, -26, 99, 8, 7, 8), 5);
      f = smin(f, n * nose_scale, 5);
    }
  }
  // Eye sockets carved under the brow, eyeballs and lids put back.
  if (!ellipsoid_above(m, 33, 14, 96, 18, 10, 12, 9 - f)) f = smax(f, -ellipsoid(m, 33, 14, 96, 18, 10, 12), 9);
  f = smin_ellipsoid(f, m, 33, 13, 80, 13, 11, 12, 3);
  // Ears (simple bumps with a helix rim).
  f = smin_ellipsoid(f, m, 80, 2, -28, 7, 26, 17, 5);
  // Neck: elliptic cylinder leaning forward, cut flat at the bottom.
  {
    const double t = (y + 160.0) / 120.0;  // 0 at the cut, 1 under the skull
    const double cz = -40.0 + 20.0 * t;
    const double k0 = std::sqrt(ax * ax / (56.0 * 56.0) + (z - cz) * (z - cz) / (62.0 * 62.0));
    double n = (k0 - 1.0) * 56.0;
    n = smax(n, y + 20.0, 10);  // top of the neck is inside the head
    f = smin(f, n, 14);
  }
  return std::max(f, kNeckCutY - y);
}

double HeadShape::sx(double qy) const {
  // Lateral scale by height: cranium above the brow, face at the cheekbones, jaw below.
  const double a = smoothstep(15, 40, qy), b = smoothstep(-65, -25, qy);
  return b * ((1 - a) * s_fw_ + a * s_hb_) + (1 - b) * s_jw_;
}

double HeadShape::value(const Point& p) const {
  const double dy = p.y() - kSellionY;
  const double qy = kSellionY + dy / (dy >= 0 ? s_hh_ : s_fl_);
  return base_value(Point(p.x() / sx(qy), qy, p.z() / s_hl_));
}

Point HeadShape::ray_hit(const Vector& dir) const {
  const Vector d = dir / std::sqrt(dir.squared_length());
  const double step = 1.5, r_max = 300.0;  // parts are > 10 mm thick, so 1.5 mm steps miss none
  double r = r_max;
  while (r > 0 && value(centre_ + r * d) > 0) r -= step;
  if (r <= 0) return centre_;
  double lo = r, hi = r + step;  // value(lo) <= 0 < value(hi)
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (value(centre_ + mid * d) > 0 ? hi : lo) = mid;
  }
  return centre_ + 0.5 * (lo + hi) * d;
}

bool HeadShape::front_hit(double x, double y, Point* hit) const {
  const double step = 1.0;
  double z = 250.0;
  while (z > -250.0 && value(Point(x, y, z)) > 0) z -= step;
  if (z <= -250.0) return false;
  double lo = z, hi = z + step;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (value(Point(x, y, mid)) > 0 ? hi : lo) = mid;
  }
  *hit = Point(x, y, 0.5 * (lo + hi));
  return true;
}

Vector HeadShape::normal(const Point& p) const {
  const double h = 0.05;
  const Vector g(value(p + Vector(h, 0, 0)) - value(p - Vector(h, 0, 0)),
                 value(p + Vector(0, h, 0)) - value(p - Vector(0, h, 0)),
                 value(p + Vector(0, 0, h)) - value(p - Vector(0, 0, h)));
  return g / std::sqrt(g.squared_length());
}

Triangles HeadShape::mesh(int level) const {
  // Icosahedron, subdivided with shared edge midpoints, projected to directions.
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vector> dir{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                          {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<std::size_t, 3>> faces{
      {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
      {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<std::size_t, std::size_t>, std::size_t> mid;
    auto midpoint = [&](std::size_t a, std::size_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      Vector v = dir[a] / std::sqrt(dir[a].squared_length()) + dir[b] / std::sqrt(dir[b].squared_length());
      dir.push_back(v);
      return mid[key] = dir.size() - 1;
    };
    std::vector<std::array<std::size_t, 3>> next;
    next.reserve(faces.size() * 4);
    for (const auto& f : faces) {
      const std::size_t a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      next.push_back({f[0], a, c});
      next.push_back({f[1], b, a});
      next.push_back({f[2], c, b});
      next.push_back({a, b, c});
    }
    faces.swap(next);
  }
  Triangles tri;
  tri.points.resize(dir.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (long i = 0; i < long(dir.size()); ++i) tri.points[i] = ray_hit(dir[i]);
  tri.faces = faces;  // icosahedron faces are counter-clockwise seen from outside
  return tri;
}

std::vector<Hole> HeadShape::scanner_holes() const {
  std::vector<Hole> holes;
  // Under the chin: the scanner looks from the front and the sides, never from below.
  const Point chin = ray_hit(Vector(0, -1.0, 0.55));
  holes.push_back({chin, normal(chin), 12.0});
  // In the ears: the concha and the fold behind the helix are shadowed.
  for (double side : {-1.0, 1.0}) {
    const Point ear = ray_hit(Vector(side, 0.12, -0.22));
    holes.push_back({ear, normal(ear), 7.0});
  }
  return holes;
}

HeadShape::HeadShape(const HeadParams& target) : centre_(0, -10, 0) {
  // The alae of the design are 40 mm apart; the cheeks beside them make a measured nose
  // breadth a poor feedback signal, so the breadth is set directly.
  s_nb_ = target.nose_breadth / 40.0;
  // Calibrate the warp: measure the design, scale each dimension by target / measured, and
  // repeat (the warps interact a little: three rounds bring every dimension within ~0.5 mm).
  for (int round = 0; round < 3; ++round) {
    const HeadDimensions d = measure_head(mesh(6), "generated head");
    s_fl_ *= target.face_length / d.face_length;
    s_fw_ *= target.face_width / d.face_width;
    s_jw_ *= target.jaw_width / d.jaw_width;
    s_hb_ *= target.head_breadth / d.head_breadth;
    s_hl_ *= target.head_length / d.head_length;
    s_hh_ *= target.head_height / d.head_height;
    s_np_ = std::clamp(s_np_ * target.nose_protrusion / d.nose_protrusion, 0.6, 1.6);
  }
}

}  // namespace generator
