// make_straps: strap centre lines follow the convex outline of the head in the slab of the strap
// plane through the attachment points and a point on the back of the head (hand-written: a 2-D
// hull of a slab of triangles, offset by a disc; distances and the crossing check use CGAL).
#include "meshing/straps.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_2.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <set>

#include "layering/internal/layers_columns.h"
#include "layering/internal/layers_geometry.h"
#include "meshing/internal/assemble_geometry.h"
#include "pipeline/error.h"

namespace meshing {
namespace {

using layering::Block;
using layering::FeModel;
using Point2 = CGAL::Exact_predicates_inexact_constructions_kernel::Point_2;

struct Attach {
  Eigen::Vector3d left, right;
};

// Rim nodes nearest to the heights ymid ± H/4 on each side: the top and bottom strap attachments.
// A node is preferred to one up to 0.2 mm nearer that height per mm it lies further out to the
// side, so where the rim runs nearly level the strap pulls from the cup's side rather than its
// middle. (The weight dates from the first straps; on the tests' dome the attachments lie 1.8 mm
// from the exact quarter heights, within the 3 % of the rim height the tests allow.)
void attachments(const FeModel& resp, const Eigen::Vector3d& shift, Attach* top, Attach* bottom) {
  constexpr double lateral_preference = 0.2;  // mm of height per mm of |x|
  const std::vector<int> rim = rim_nodes(resp);
  double ylo = 1e300, yhi = -1e300;
  for (int i : rim) ylo = std::min(ylo, resp.nodes[i].y()), yhi = std::max(yhi, resp.nodes[i].y());
  const double ymid = 0.5 * (ylo + yhi), q = 0.25 * (yhi - ylo);
  auto pick = [&](double y, int side) {
    int best = -1;
    for (int i : rim)
      if (resp.nodes[i].x() * side > 0 &&
          (best < 0 || std::abs(resp.nodes[i].y() - y) - lateral_preference * side * resp.nodes[i].x() <
                           std::abs(resp.nodes[best].y() - y) - lateral_preference * side * resp.nodes[best].x()))
        best = i;
    if (best < 0) throw pipeline::bad_input("respirator", "rim has no node on one side of the symmetry plane");
    return Eigen::Vector3d(resp.nodes[best] + shift);
  };
  *top = {pick(ymid + q, 1), pick(ymid + q, -1)};
  *bottom = {pick(ymid - q, 1), pick(ymid - q, -1)};
}

double lay_strap(const FeModel& head, const std::vector<std::array<int, 3>>& skin, const Attach& a, double back_y,
                 const StrapOptions& opt, const std::string& name, FeModel* out, double* outline_mm) {
  // Point on the back of the head (sagittal plane, height back_y): the rear-most skin node there,
  // among nodes within 8 mm of the midline and 6 mm of that height: a window about two skin edges
  // wide (the chain's layered skins have 4-7 mm edges), so it always holds a node.
  constexpr double midline_window_mm = 8, height_window_mm = 6;
  Eigen::Vector3d back(0, back_y, 1e300);
  for (const auto& p : head.nodes)
    if (std::abs(p.x()) < midline_window_mm && std::abs(p.y() - back_y) < height_window_mm && p.z() < back.z()) back = p;
  if (back.z() > 1e299) throw pipeline::bad_input("head", name + ": no skin at the back of the head at y = " + pipeline::format_number(back_y));
  const Eigen::Vector3d mid = 0.5 * (a.left + a.right), o = 0.5 * (mid + back);
  const Eigen::Vector3d u = (a.left - a.right).normalized();
  Eigen::Vector3d w = back - o;
  w = (w - w.dot(u) * u).normalized();
  const Eigen::Vector3d nrm = u.cross(w).normalized();
  const double lift = opt.clearance_mm + 0.5 * opt.thickness_mm;
  auto angle = [&](const Eigen::Vector3d& p) { return std::atan2((p - o).dot(w), (p - o).dot(u)); };
  double tl = angle(a.left), tr = angle(a.right);
  if (tl > M_PI / 2) tl -= 2 * M_PI;
  if (tr < M_PI / 2) tr += 2 * M_PI;
  // Outline of the head in the SLAB the band occupies and the skin within `lift` of it (|distance to
  // the strap plane| <= width/2 + lift), projected onto the plane: every skin triangle cut by the slab contributes the corners of
  // its part inside the slab (its vertices inside, its edges' crossings of the slab faces), so the
  // convex hull of these points contains the projection of all skin within the slab. A strap
  // planar section alone missed the skin beside the centre line behind the ears and the band's
  // edges cut it there. The hull is of the WHOLE slab (all around o), taken by CGAL: a scan over
  // only the angles between the attachments kept its first and last points even when they were
  // inner skin (cheek under the ear), and the band started inside the head (-1.7 mm, 320 mm strap).
  // Any skin within `lift` of a band node lies in this slab, so inside the hull, which the band's
  // path clears by `lift` in the plane and so in space. The slab was width/2 + 1 mm: skin just
  // beyond it (behind the ears) came to 1.45 mm of a band laid for 1 mm (lift 1.5) and to 2.32 mm
  // of one laid for 5 mm (lift 3.5), whose shell then began inside the head.
  const double half_slab = 0.5 * opt.width_mm + lift;
  std::vector<Point2> pts;
  for (const auto& tri : skin) {
    double h[3];
    for (int v = 0; v < 3; ++v) h[v] = (head.nodes[tri[v]] - o).dot(nrm);
    for (int v = 0; v < 3; ++v) {
      const Eigen::Vector3d& p = head.nodes[tri[v]];
      const Eigen::Vector3d& q = head.nodes[tri[(v + 1) % 3]];
      const double hp = h[v], hq = h[(v + 1) % 3];
      auto add_point = [&](const Eigen::Vector3d& x) { pts.emplace_back((x - o).dot(u), (x - o).dot(w)); };
      if (std::abs(hp) <= half_slab) add_point(p);
      for (double face : {-half_slab, half_slab})
        if ((hp - face) * (hq - face) < 0) add_point(p + (q - p) * ((face - hp) / (hq - hp)));
    }
  }
  if (pts.size() < 10) throw pipeline::bad_input("head", name + ": the strap plane misses the head");
  std::vector<Point2> hull_pts;
  CGAL::convex_hull_2(pts.begin(), pts.end(), std::back_inserter(hull_pts));  // counter-clockwise
  const int nh = int(hull_pts.size());
  std::vector<Eigen::Vector2d> hull_ccw(nh);
  for (int i = 0; i < nh; ++i) hull_ccw[i] = {hull_pts[i].x(), hull_pts[i].y()};
  // Where the ray from o at angle t leaves the hull: (edge index, point). o is inside the head's
  // section, hence inside the hull, so exactly one edge is hit.
  auto ray_exit = [&](double t, Eigen::Vector2d* hit) {
    const Eigen::Vector2d d(std::cos(t), std::sin(t));
    for (int i = 0; i < nh; ++i) {
      const Eigen::Vector2d a = hull_ccw[i], e = hull_ccw[(i + 1) % nh] - a;
      const double den = d.x() * e.y() - d.y() * e.x();  // solve r d = a + f e
      if (std::abs(den) < 1e-12) continue;
      const double r = (a.x() * e.y() - a.y() * e.x()) / den, f = (a.x() * d.y() - a.y() * d.x()) / den;
      if (r > 0 && f >= 0 && f <= 1) {
        *hit = r * d;
        return i;
      }
    }
    throw pipeline::algorithm_failed(name, "strap centre is outside the head's section");
  };
  // Chain from the left attachment's ray over the back to the right one's: angles increase from tl
  // to tr, i.e. counter-clockwise, the hull's own order.
  Eigen::Vector2d start, end;
  const int i0 = ray_exit(tl, &start), i1 = ray_exit(tr, &end);
  std::vector<Eigen::Vector2d> hull{start};
  for (int i = (i0 + 1) % nh;; i = (i + 1) % nh) {
    if ((hull_ccw[i] - hull.back()).norm() > 1e-9) hull.push_back(hull_ccw[i]);
    if (i == i1) break;
  }
  if ((end - hull.back()).norm() > 1e-9) hull.push_back(end);
  if (hull.size() < 2) throw pipeline::algorithm_failed(name, "empty outline between the attachments");
  // Offset the chain outward by `lift` (Minkowski sum with a disc: shifted segments joined by arcs,
  // no self-intersection on a convex chain), sampled every ~1 mm, back in 3D.
  std::vector<Eigen::Vector2d> off;
  auto outward = [&](std::size_t i) {  // of segment i → i+1: right of the direction of travel
    const Eigen::Vector2d e = (hull[i + 1] - hull[i]).normalized();
    return Eigen::Vector2d(e.y(), -e.x());
  };
  for (std::size_t i = 0; i + 1 < hull.size(); ++i) {
    const Eigen::Vector2d nv = outward(i);
    if (i > 0) {  // round join at hull[i] from the previous segment's normal to this one's
      const Eigen::Vector2d np = outward(i - 1);
      const double a0 = std::atan2(np.y(), np.x());
      double a1 = std::atan2(nv.y(), nv.x());
      while (a1 < a0) a1 += 2 * M_PI;  // a convex chain turns left: its normals turn counter-clockwise
      while (a1 > a0 + M_PI) a1 -= 2 * M_PI;
      const int m = std::max(1, int(std::ceil(std::abs(a1 - a0) * lift / 1.0)));
      for (int j = 0; j < m; ++j) {
        const double a = a0 + (a1 - a0) * j / m;
        off.push_back(hull[i] + lift * Eigen::Vector2d(std::cos(a), std::sin(a)));
      }
    }
    const Eigen::Vector2d a = hull[i] + lift * nv, b = hull[i + 1] + lift * nv;
    const int m = std::max(1, int(std::ceil((b - a).norm() / 1.0)));
    for (int j = 0; j < m; ++j) off.push_back(a + (b - a) * (double(j) / m));
    if (i + 2 == hull.size()) off.push_back(b);
  }
  std::vector<Eigen::Vector3d> path;
  for (const auto& q : off) path.push_back(o + q.x() * u + q.y() * w);
  std::vector<double> s(path.size(), 0.0);
  for (std::size_t i = 1; i < path.size(); ++i) s[i] = s[i - 1] + (path[i] - path[i - 1]).norm();
  std::size_t ib = 0;
  for (std::size_t i = 0; i < path.size(); ++i)
    if ((path[i] - back).norm() < (path[ib] - back).norm()) ib = i;
  *outline_mm = s.back();
  const double stretch_percent = 100.0 * (s.back() / opt.length_mm - 1.0);
  if (stretch_percent > opt.max_stretch_percent)
    throw pipeline::bad_input("--length-mm", name + ": a " + pipeline::format_number(opt.length_mm) + " mm strap would stretch " +
                                                 pipeline::format_number(std::round(stretch_percent)) + " % to reach round the head (" +
                                                 pipeline::format_number(std::round(s.back())) + " mm between its attachment points), more than " +
                                                 pipeline::format_number(opt.max_stretch_percent) + " % (--max-stretch-percent): is the length in mm?");
  const double s0 = s[ib] - 0.5 * opt.length_mm, s1 = s[ib] + 0.5 * opt.length_mm;
  // The band is centred on the back of the head, so what fits is twice the shorter side: a 384 mm
  // strap "exceeded" an outline of 384.012 mm, which it does not.
  if (s0 < 0 || s1 > s.back()) {
    const double fits_mm = 2 * std::min(s[ib], s.back() - s[ib]);
    throw pipeline::bad_input("--length-mm", name + ": a " + pipeline::format_number(opt.length_mm) +
                                                 " mm strap centred on the back of the head runs past an attachment point: "
                                                 "at most " + pipeline::format_number(std::floor(fits_mm * 10) / 10) +
                                                 " mm fits (the outline between the attachment points is " +
                                                 pipeline::format_number(std::round(s.back() * 10) / 10) +
                                                 " mm): a shorter strap (through make, STRAP_LENGTH_MM=), or a head "
                                                 "smaller than it is (its back filled in, its tragia off the ears: see "
                                                 "repair's and landmarks' warnings)?");
  }
  const int n = std::max(2, int(std::ceil(opt.length_mm / opt.element_mm)));
  const int base = int(out->nodes.size());
  // Nodes: n+1 stations × 3 across the width (centre and both edges).
  std::size_t k = 0;
  for (int i = 0; i <= n; ++i) {
    const double si = s0 + (s1 - s0) * i / n;
    while (k + 2 < s.size() && s[k + 1] < si) ++k;
    const double f = (si - s[k]) / std::max(1e-12, s[k + 1] - s[k]);
    const Eigen::Vector3d c = path[k] + f * (path[k + 1] - path[k]);
    // Across the band: the strap plane's normal, so the whole band stays inside the slab whose
    // skin the offset hull clears by `lift` (it stands off where the head slopes across the plane;
    // stage I's wrapping lays it down).
    const Eigen::Vector3d across = nrm;
    for (int j = -1; j <= 1; ++j) out->nodes.push_back(c + j * 0.5 * opt.width_mm * across);
  }
  Block band{name, 2, 4, {}};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2; ++j) {
      const int a0 = base + 3 * i + j, a1 = base + 3 * (i + 1) + j;
      // Outward normal (away from the head centre o) by the right-hand rule.
      const Eigen::Vector3d nq = (out->nodes[a1] - out->nodes[a0]).cross(out->nodes[a0 + 1] - out->nodes[a0]);
      if (nq.dot(out->nodes[a0] - o) > 0) band.conn.insert(band.conn.end(), {a0, a1, a1 + 1, a0 + 1});
      else band.conn.insert(band.conn.end(), {a0, a0 + 1, a1 + 1, a1});
    }
  out->blocks.push_back(band);
  // Station 0 lies on the left attachment's side (t increases from left to right).
  for (auto [side, st] : {std::pair<const char*, int>{"left", 0}, {"right", n}}) {
    const int b0 = base + 3 * st;
    out->blocks.push_back(Block{name + "_end_" + side, 1, 2, {b0, b0 + 1, b0 + 1, b0 + 2}});
    out->nodes.push_back(std::string(side) == "left" ? a.left : a.right);
    out->blocks.push_back(Block{name + "_attach_" + side, 0, 1, {int(out->nodes.size()) - 1}});
  }
  double len = 0;
  for (int i = 0; i < n; ++i) len += (out->nodes[base + 3 * (i + 1) + 1] - out->nodes[base + 3 * i + 1]).norm();
  return len;
}

}  // namespace

FeModel make_straps(const FeModel& head, const std::map<std::string, Eigen::Vector3d>& lm, const FeModel& resp,
                    const StrapOptions& opt, StrapReport* report) {
  const Eigen::Vector3d shift = place_respirator(head, lm, resp, opt.place, nullptr);
  Attach top, bottom;
  attachments(resp, shift, &top, &bottom);
  const std::vector<std::array<int, 3>> skin = head_surface(head);
  internal::TriangleTree tree(head.nodes, skin);
  FeModel out;
  StrapReport r;
  // The top strap passes ABOVE the ears: if the tragia are known, raise its back point until the
  // strap plane is 35 mm above the tragion where it passes the ear (an ear reaches ~30 mm above
  // the tragion; a strap cutting through it cannot be laid without crossing the skin).
  double top_y = lm.at("sellion").y() + opt.top_above_sellion_mm;
  if (lm.count("tragion_left") && lm.count("tragion_right")) {
    const Eigen::Vector3d tr = 0.5 * (lm.at("tragion_left") + lm.at("tragion_right"));
    const Eigen::Vector3d a = 0.5 * (top.left + top.right);
    double zb = 1e300;
    for (const auto& p : head.nodes) zb = std::min(zb, p.z());
    const double f = (a.z() - tr.z()) / std::max(1e-9, a.z() - zb);  // fraction of the way to the back
    if (f > 0.05 && f < 1) top_y = std::max(top_y, (tr.y() + 35 - (1 - f) * a.y()) / f);
    // That raise extrapolates from the attachments (f can be small), and a low attachment on a
    // short head asked for y = 149 mm on NIOSH medium, above its crown: keep the back point at
    // least 15 mm below the highest skin behind the ears in the sagittal band. If the strap then
    // grazes an ear, the crossing fix below pushes it out.
    double crown_y = -1e300;
    for (const auto& p : head.nodes)
      if (std::abs(p.x()) < 8 && p.z() < tr.z()) crown_y = std::max(crown_y, p.y());
    if (crown_y > -1e299) top_y = std::min(top_y, crown_y - 15);
  }
  r.top_back_y = top_y;
  r.top_length = lay_strap(head, skin, top, top_y, opt, "strap_top", &out, &r.top_outline);
  const int bottom_base = int(out.nodes.size());
  r.bottom_length = lay_strap(head, skin, bottom, lm.at("menton").y() - opt.bottom_below_menton_mm, opt, "strap_bottom", &out,
                             &r.bottom_outline);
  // Detect and fix: a quad can still cut through a thin skin feature (ear rim) between its nodes,
  // which are all off the skin. Push the nodes of every crossing strap face 1 mm further out along
  // the direction from their closest skin point, until no strap face crosses the skin.
  for (int pass = 0; pass < 12; ++pass) {
    FeModel check;
    check.nodes = head.nodes;
    const int base = int(check.nodes.size());
    check.nodes.insert(check.nodes.end(), out.nodes.begin(), out.nodes.end());
    check.blocks.push_back(Block{"skin", 2, 3, {}});
    for (const auto& t : head_surface(head)) check.blocks[0].conn.insert(check.blocks[0].conn.end(), t.begin(), t.end());
    for (Block b : out.blocks)
      if (b.dim == 2) {
        for (int& v : b.conn) v += base;
        check.blocks.push_back(b);
      }
    std::vector<std::array<int, 3>> faces;
    std::vector<std::pair<int, int>> owner;
    layering::internal::element_faces(check, &faces, &owner);
    std::set<int> push;
    for (auto [a, b] : layering::internal::intersecting_triangles(check.nodes, faces))
      for (int f : {a, b})
        if (owner[f].first > 0)
          for (int v : faces[f]) push.insert(v - base);
    if (push.empty()) break;
    if (pass == 11) {
      const Eigen::Vector3d& q = out.nodes[*push.begin()];
      throw pipeline::algorithm_failed("strap layout", std::to_string(push.size()) + " strap nodes still on faces crossing the skin, e.g. near (" +
                                                     pipeline::format_number(q.x()) + ", " + pipeline::format_number(q.y()) + ", " + pipeline::format_number(q.z()) + ") mm");
    }
    for (int v : push) {
      // 1 mm away from the skin: along the line from the nearest skin point, or along the skin's
      // outward normal for a node on or inside the skin (the line gave NaN, or pushed it further
      // in: sweep Q; no strap node has come that near in any case or test).
      Eigen::Vector3d cp, normal;
      const double d = tree.signed_distance(out.nodes[v], &cp, &normal);
      out.nodes[v] += d > 1e-9 ? Eigen::Vector3d((out.nodes[v] - cp).normalized()) : normal.normalized();
    }
  }
  // Centre-line lengths after the fix (stations: 3 nodes each, centre in the middle).
  auto centre_length = [&](int base, const char* band) {
    const int n = int(out.find(band)->size() / 2);
    double len = 0;
    for (int i = 0; i < n; ++i) len += (out.nodes[base + 3 * (i + 1) + 1] - out.nodes[base + 3 * i + 1]).norm();
    return len;
  };
  r.top_length = centre_length(0, "strap_top");
  r.bottom_length = centre_length(bottom_base, "strap_bottom");
  r.min_gap = 1e300;
  for (const Block& b : out.blocks)
    if (b.dim == 2) {
      r.quads += b.size();
      for (int v : b.conn) {
        const double d = tree.signed_distance(out.nodes[v]);
        if (d < r.min_gap) r.min_gap = d, r.min_gap_at = out.nodes[v];
      }
    }
  if (report) *report = r;
  return out;
}

}  // namespace meshing
