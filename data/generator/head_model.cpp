#include "data/generator/head_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <string>
#include <unordered_map>
#include <nlohmann/json.hpp>

#include "pipeline/error.h"
#include "pipeline/read_json.h"

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

/// An ellipsoidal part of the design: centre c, radii r [mm], blended with smooth radius k into
/// what comes before it. A mirrored part is written for the +x side and applies to |x|.
struct EllipsoidPart {
  bool mirrored;
  double cx, cy, cz, rx, ry, rz, k;
  double r_min, r_max, inv_r_min, inv_rx2, inv_ry2, inv_rz2;  // derived, for the bounds below
  double value(const Point& p) const { return ellipsoid(p, cx, cy, cz, rx, ry, rz); }
};
constexpr EllipsoidPart part(bool mirrored, double cx, double cy, double cz, double rx, double ry, double rz,
                             double k) {
  return {mirrored, cx, cy, cz, rx, ry, rz, k, std::min({rx, ry, rz}), std::max({rx, ry, rz}),
          1 / std::min({rx, ry, rz}), 1 / (rx * rx), 1 / (ry * ry), 1 / (rz * rz)};
}

// Bounds of ellipsoid(): with u = p − c, k0 = |u/r| and k1 = |u/r²|, k0/k1 is a weighted mean
// of the radii, so it lies in [r_min, r_max], and the value k0(k0 − 1)/k1 is at least
// g(k0) = (k0 − 1)·r_min for k0 ≥ 1 and (k0 − 1)·r_max below (the branch for k1 ≈ 0 returns
// −r_min ≥ g(0)). g increases with k0.
inline double part_bound_of_k0(const EllipsoidPart& e, double k0) { return (k0 - 1.0) * (k0 >= 1.0 ? e.r_min : e.r_max); }

/// True if e.value(p) > t for certain: g(k0) > max(t, 0) when k0 > 1 + max(t, 0)/r_min.
inline bool part_above(const EllipsoidPart& e, const Point& p, double t) {
  const double x = p.x() - e.cx, y = p.y() - e.cy, z = p.z() - e.cz;
  const double k0_needed = 1.0 + (std::max(t, 0.0) + kCullSlack) * e.inv_r_min;
  return x * x * e.inv_rx2 + y * y * e.inv_ry2 + z * z * e.inv_rz2 > k0_needed * k0_needed;
}
/// smin(f, e.value(p), e.k), skipping the ellipsoid where it cannot change f.
inline double smin_part(double f, const EllipsoidPart& e, const Point& q, const Point& q_mirrored) {
  const Point& p = e.mirrored ? q_mirrored : q;
  if (part_above(e, p, f + e.k)) return f;
  return smin(f, e.value(p), e.k);
}

/// Axis-aligned box [lo, hi] in the design's frame.
struct Box {
  std::array<double, 3> lo, hi;
};
/// Distance from the interval [lo, hi] to c along one axis.
inline double axis_gap(double lo, double hi, double c) { return std::max({lo - c, c - hi, 0.0}); }
/// Lower bound of e.value over the box: g(smallest k0 in the box).
double part_lower_bound(const EllipsoidPart& e, const Box& b) {
  double x_lo = b.lo[0], x_hi = b.hi[0];
  if (e.mirrored) {  // |x| over [x_lo, x_hi]
    const double a = std::abs(x_lo), c = std::abs(x_hi);
    x_lo = x_lo <= 0 && x_hi >= 0 ? 0.0 : std::min(a, c);
    x_hi = std::max(a, c);
  }
  const double gx = axis_gap(x_lo, x_hi, e.cx), gy = axis_gap(b.lo[1], b.hi[1], e.cy),
               gz = axis_gap(b.lo[2], b.hi[2], e.cz);
  return part_bound_of_k0(e, std::sqrt(gx * gx * e.inv_rx2 + gy * gy * e.inv_ry2 + gz * gz * e.inv_rz2));
}

// The design, in blending order. Skull and face before the nose:
constexpr std::array<EllipsoidPart, 12> kSkullParts{{
    part(false, 0, 30, 2, 76, 95, 97, 0),        // cranium (first: no blend)
    part(false, 0, 20, -42, 71, 78, 55, 10),     // occiput
    part(false, 0, 45, 40, 66, 55, 60, 12),      // broad, flat forehead
    part(false, 0, 34, 82, 56, 12, 18, 8),       // brow ridge, forehead-to-nose
    part(false, 0, -28, 28, 72, 60, 68, 10),     // mid-face (maxilla)
    part(true, 44, 2, 52, 22, 16, 26, 10),       // cheekbones
    part(true, 63, 3, 14, 11, 10, 42, 8),        // zygomatic arches
    part(false, 0, -70, 36, 52, 30, 58, 12),     // mandible body
    part(true, 48, -66, -4, 12, 22, 18, 10),     // mandible angles (gonion)
    part(false, 0, -86, 74, 22, 13, 16, 12),     // chin
    part(false, 0, -46, 90, 20, 10, 12, 10),     // upper lip
    part(false, 0, -62, 88, 18, 9, 11, 10)}};    // lower lip
// Nose (in its own scaled frame): bridge capsule from the sellion to the tip, tip, alae.
constexpr double kNoseBaseZ = 90.0;  // nose base depth: protrusion is scaled from here
constexpr double kNoseBlend = 5;
constexpr EllipsoidPart kNoseTip = part(false, 0, -18, 107, 10, 9, 10, 6);
constexpr EllipsoidPart kAla = part(true, 12, -26, 99, 8, 7, 8, 5);
const Point kBridgeTop(0, 18, 92), kBridgeTip(0, -14, 104);
const Point kBridgeMid = CGAL::midpoint(kBridgeTop, kBridgeTip);
const double kBridgeHalfLength = 0.5 * std::sqrt((kBridgeTip - kBridgeTop).squared_length());
constexpr double kBridgeMaxRadius = 8.0;  // radius goes from 5.5 at the top to 8 at the tip
// Eye sockets carved under the brow (smooth maximum), then eyeballs and lids, ears.
constexpr EllipsoidPart kEyeSocket = part(true, 33, 14, 96, 18, 10, 12, 9);
// The ears are half-buried domes (centre x = 70, about the scalp's half-width there), not discs
// standing off the scalp: a disc's walls overhang the scalp as seen from the mesh's ray origin,
// and the ray-cast mesh then bridged the hidden wall with a skirt up to 16 mm off the implicit
// surface, whose sharp edges every reconstruction rounds (tests/data/generated_models_test.cpp,
// every_ray_from_the_centre_crosses_the_surface_once).
constexpr std::array<EllipsoidPart, 2> kLateParts{{
    part(true, 33, 13, 80, 13, 11, 12, 3),     // eyeballs and lids
    part(true, 70, 2, -28, 16, 26, 17, 10)}};  // ears (simple domes)

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
constexpr double kNeckCutRound = 8.0;  // [mm]

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
  return head_params_from_json(pipeline::read_json(path), path, id);
}

HeadParams head_params_from_json(const nlohmann::json& j, const std::string& path, const std::string& id) {
  if (!j.contains("headforms") || !j["headforms"].is_object())
    throw pipeline::bad_input(path, "no \"headforms\" object");
  if (!j["headforms"].contains(id)) {
    std::string known;
    for (auto it = j["headforms"].begin(); it != j["headforms"].end(); ++it) known += " " + it.key();
    throw pipeline::bad_input(path, "unknown headform id '" + id + "', known:" + known);
  }
  const auto& h = j["headforms"][id];
  // every dimension is required, but an added one ("chin_protrusion": 12) was read by no one
  std::set<std::string> known;
  for (const Range& r : kFields) known.insert(r.name);
  if (const std::string key = pipeline::first_unknown_key(h, known); !key.empty())
    throw pipeline::bad_input(path, "headform '" + id + "': unknown key \"" + key + "\"");
  HeadParams p;
  for (const Range& r : kFields) {
    if (!h.contains(r.name) || !h[r.name].is_number())
      throw pipeline::bad_input(path, "headform '" + id + "': missing number \"" + r.name + "\"");
    const double v = h[r.name].get<double>();
    if (!(v >= r.lo && v <= r.hi))
      throw pipeline::bad_input(path, "headform '" + id + "': " + r.name + " = " + pipeline::format_number(v) +
                                          " mm, expected " + pipeline::format_number(r.lo) + ".." +
                                          pipeline::format_number(r.hi));
    p.*(r.field) = v;
  }
  // Each dimension in its range is not yet a head: a jaw wider than the face, or a cranium
  // narrower than the cheekbones, was built as asked (calibrated to 0.4 mm) with exit 0, a pinched
  // face over a wide jaw. The bounds hold with room on NIOSH medium and large and the five
  // headforms here: jaw / face width 0.70-0.77, face width - head breadth -3.2 to +1.8 mm, head
  // breadth / length 0.74-0.83.
  const auto refuse = [&](const std::string& what) {
    throw pipeline::bad_input(path, "headform '" + id + "': " + what + ": no head is built so");
  };
  using pipeline::format_number;
  if (!(p.jaw_width < p.face_width))
    refuse("jaw_width " + format_number(p.jaw_width) + " mm is not under face_width " + format_number(p.face_width) + " mm");
  if (!(p.face_width <= p.head_breadth + 15))
    refuse("face_width " + format_number(p.face_width) + " mm is more than 15 mm over head_breadth " +
           format_number(p.head_breadth) + " mm");
  if (!(p.head_breadth < p.head_length))
    refuse("head_breadth " + format_number(p.head_breadth) + " mm is not under head_length " +
           format_number(p.head_length) + " mm");
  return p;
}

double HeadShape::base_value(const Point& q) const {
  const double x = q.x(), ax = std::abs(x), y = q.y(), z = q.z();
  const Point m(ax, y, z);  // mirrored: paired parts are written for the +x side only
  double f = kSkullParts[0].value(q);
  for (std::size_t i = 1; i < kSkullParts.size(); ++i) f = smin_part(f, kSkullParts[i], q, m);
  // Nose: scaled in depth and breadth.
  {
    const Point qn(x / s_nb_, y, kNoseBaseZ + (z - kNoseBaseZ) / s_np_);
    const Point qn_mirrored(std::abs(qn.x()), qn.y(), qn.z());
    const double nose_scale = std::min(s_nb_, s_np_);  // > 0
    // Culling the whole nose: n ≥ min(capsule, tip, alae) − 6/4 − 5/4 (each smin lowers the
    // minimum by at most k/4), so f is unchanged when all three exceed t_nose. The capsule is
    // at least its distance to the segment's midpoint minus half its length and its largest
    // radius (8 mm).
    const double t_nose =
        std::max((f + kNoseBlend + kCullSlack) / nose_scale + 0.25 * (kNoseTip.k + kAla.k), 0.0);
    const double capsule_reach = kBridgeHalfLength + kBridgeMaxRadius + t_nose + kCullSlack;
    const bool nose_far = (qn - kBridgeMid).squared_length() > capsule_reach * capsule_reach &&
                          part_above(kNoseTip, qn, t_nose) && part_above(kAla, qn_mirrored, t_nose);
    if (!nose_far) {
      double n = tapered_capsule(qn, kBridgeTop, kBridgeTip, 5.5, kBridgeMaxRadius);
      n = smin(n, kNoseTip.value(qn), kNoseTip.k);
      n = smin(n, kAla.value(qn_mirrored), kAla.k);
      f = smin(f, n * nose_scale, kNoseBlend);
    }
  }
  if (!part_above(kEyeSocket, m, kEyeSocket.k - f)) f = smax(f, -kEyeSocket.value(m), kEyeSocket.k);
  for (const EllipsoidPart& e : kLateParts) f = smin_part(f, e, q, m);
  // Neck: elliptic cylinder leaning forward, cut flat at the bottom. Its value is at least
  // y + 20 (the smax below), so above y = f − 6 it cannot change f (see kCullSlack).
  if (!(y + 20.0 > f + 14 + kCullSlack)) {
    const double t = (y + 160.0) / 120.0;  // 0 at the cut, 1 under the skull
    const double cz = -40.0 + 20.0 * t;
    const double k0 = std::sqrt(ax * ax / (56.0 * 56.0) + (z - cz) * (z - cz) / (62.0 * 62.0));
    double n = (k0 - 1.0) * 56.0;
    n = smax(n, y + 20.0, 10);  // top of the neck is inside the head
    f = smin(f, n, 14);
  }
  // The flat cut's rim is rounded (blend radius kNeckCutRound): a sharp 90° rim is the one edge
  // a smoothing reconstruction cannot follow (1.0-1.1 mm off on the generated heads' scans), and
  // a headform's cut neck is not a knife edge. smax >= max, so provably_outside's bound holds.
  return smax(f, kNeckCutY - y, kNeckCutRound);
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

bool HeadShape::provably_outside(const Point& a, const Point& b) const {
  // Box of the segment in the warped design frame of value(): q.y increases with p.y (two
  // positive slopes meeting at the sellion), q.z = p.z/s_hl, and q.x = p.x/sx(q.y) with sx a
  // convex combination of s_fw, s_hb, s_jw. The pad (1e-6 mm) covers rounding of the points.
  const double pad = 1e-6;
  auto warp_y = [&](double py) {
    const double dy = py - kSellionY;
    return kSellionY + dy / (dy >= 0 ? s_hh_ : s_fl_);
  };
  const double s_lo = std::min({s_fw_, s_hb_, s_jw_}), s_hi = std::max({s_fw_, s_hb_, s_jw_});
  const double x_lo = std::min(a.x(), b.x()), x_hi = std::max(a.x(), b.x());
  const std::array<double, 4> qx{x_lo / s_lo, x_lo / s_hi, x_hi / s_lo, x_hi / s_hi};
  const Box q{{*std::min_element(qx.begin(), qx.end()) - pad, warp_y(std::min(a.y(), b.y())) - pad,
               std::min(a.z(), b.z()) / s_hl_ - pad},
              {*std::max_element(qx.begin(), qx.end()) + pad, warp_y(std::max(a.y(), b.y())) + pad,
               std::max(a.z(), b.z()) / s_hl_ + pad}};
  if (q.hi[1] < kNeckCutY) return true;  // below the flat cut
  // Lower bound of base_value over the box: the same blend with a lower bound in place of each
  // part (smin is nondecreasing in both arguments, n·scale in n; smax(f, ·) ≥ f, so the eye
  // sockets are left out). smin(a, b, k) ≤ a, so the bound only falls from part to part: once
  // it is not above the slack, the answer is no.
  double f = part_lower_bound(kSkullParts[0], q);
  for (std::size_t i = 1; i < kSkullParts.size() && f > kCullSlack; ++i)
    f = smin(f, part_lower_bound(kSkullParts[i], q), kSkullParts[i].k);
  if (!(f > kCullSlack)) return false;
  {
    // The box in the nose's frame; the capsule is at least the distance to its midpoint minus
    // half its length and its largest radius.
    Box qn = q;
    qn.lo[0] = q.lo[0] / s_nb_, qn.hi[0] = q.hi[0] / s_nb_;
    qn.lo[2] = kNoseBaseZ + (q.lo[2] - kNoseBaseZ) / s_np_, qn.hi[2] = kNoseBaseZ + (q.hi[2] - kNoseBaseZ) / s_np_;
    const double gx = axis_gap(qn.lo[0], qn.hi[0], kBridgeMid.x()), gy = axis_gap(qn.lo[1], qn.hi[1], kBridgeMid.y()),
                 gz = axis_gap(qn.lo[2], qn.hi[2], kBridgeMid.z());
    double n = std::sqrt(gx * gx + gy * gy + gz * gz) - kBridgeHalfLength - kBridgeMaxRadius;
    n = smin(n, part_lower_bound(kNoseTip, qn), kNoseTip.k);
    n = smin(n, part_lower_bound(kAla, qn), kAla.k);
    f = smin(f, n * std::min(s_nb_, s_np_), kNoseBlend);
  }
  for (const EllipsoidPart& e : kLateParts) f = smin(f, part_lower_bound(e, q), e.k);
  if (!(f > kCullSlack)) return false;
  {
    // Neck: n = smax((k0 − 1)·56, y + 20, 10) ≥ both; its axis cz increases with y.
    const double cz_lo = -40.0 + 20.0 * (q.lo[1] + 160.0) / 120.0, cz_hi = -40.0 + 20.0 * (q.hi[1] + 160.0) / 120.0;
    const double gx = axis_gap(q.lo[0], q.hi[0], 0.0), gz = std::max({q.lo[2] - cz_hi, cz_lo - q.hi[2], 0.0});
    const double k0 = std::sqrt(gx * gx / (56.0 * 56.0) + gz * gz / (62.0 * 62.0));
    f = smin(f, std::max((k0 - 1.0) * 56.0, q.lo[1] + 20.0), 14);
  }
  return f > kCullSlack;
}

namespace {

/// The first k in [k_lo, k_hi] whose point at(k) is inside (!(value > 0)), or −1: the same k a
/// march testing k_lo, k_lo + 1, ... in turn stops at, but runs of lattice points whose
/// segment is provably outside are skipped whole (halving the run until it is, or is one point).
template <class At>
long first_inside(const HeadShape& head, long k_lo, long k_hi, const At& at) {
  if (k_lo == k_hi) return head.value(at(k_lo)) > 0 ? -1 : k_lo;
  if (head.provably_outside(at(k_lo), at(k_hi))) return -1;
  const long k_mid = k_lo + (k_hi - k_lo) / 2;
  const long k = first_inside(head, k_lo, k_mid, at);
  return k >= 0 ? k : first_inside(head, k_mid + 1, k_hi, at);
}

}  // namespace

Point HeadShape::ray_hit(const Vector& dir) const {
  const Vector d = dir / std::sqrt(dir.squared_length());
  const double step = 1.5, r_max = 300.0;  // parts are > 10 mm thick, so 1.5 mm steps miss none
  // March inwards over r_k = r_max − k·step > 0 (multiples of 0.5 mm: exact, the same radii as
  // subtracting the step k times) to the first point inside.
  const long k_end = long(std::ceil(r_max / step));  // r_k > 0 for k < k_end
  const long k = first_inside(*this, 0, k_end - 1, [&](long i) { return centre_ + (r_max - double(i) * step) * d; });
  if (k < 0) return centre_;
  const double r = r_max - double(k) * step;
  double lo = r, hi = r + step;  // value(lo) <= 0 < value(hi)
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (value(centre_ + mid * d) > 0 ? hi : lo) = mid;
  }
  return centre_ + 0.5 * (lo + hi) * d;
}

bool HeadShape::front_hit(double x, double y, Point* hit) const {
  const double step = 1.0, z_max = 250.0;
  // March down z_k = z_max − k·step > −z_max (integers: exact) to the first point inside.
  const long k_end = long(std::ceil(2 * z_max / step));
  const long k = first_inside(*this, 0, k_end - 1, [&](long i) { return Point(x, y, z_max - double(i) * step); });
  if (k < 0) return false;
  const double z = z_max - double(k) * step;
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
    // Edge (lower, higher vertex; < 2^32 up to level 14) -> its midpoint's index; indices follow
    // the order of first use, so the hash order does not matter.
    std::unordered_map<std::uint64_t, std::size_t> mid;
    mid.reserve(faces.size() * 3 / 2);
    auto midpoint = [&](std::size_t a, std::size_t b) {
      const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::uint64_t(std::max(a, b));
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
