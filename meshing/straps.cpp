// make_straps: strap centre lines follow the head outline in the plane through the attachment
// points and a point on the back of the head (hand-written: a planar path on a surface; the ray
// casts and distances are CGAL's AABB tree).
#include "meshing/straps.h"

#include <Eigen/Geometry>

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

struct Attach {
  Eigen::Vector3d left, right;
};

// Rim nodes nearest to the heights ymid ± H/4 on each side: the top and bottom strap attachments.
void attachments(const FeModel& resp, const Eigen::Vector3d& shift, Attach* top, Attach* bottom) {
  std::vector<int> rim;
  if (const Block* r = resp.find("respirator_rim")) rim = r->conn;
  else throw pipeline::bad_input("respirator", "no respirator_rim group (run layers --kind respirator first)");
  double ylo = 1e300, yhi = -1e300;
  for (int i : rim) ylo = std::min(ylo, resp.nodes[i].y()), yhi = std::max(yhi, resp.nodes[i].y());
  const double ymid = 0.5 * (ylo + yhi), q = 0.25 * (yhi - ylo);
  auto pick = [&](double y, int side) {
    int best = -1;
    for (int i : rim)
      if (resp.nodes[i].x() * side > 0 &&
          (best < 0 || std::abs(resp.nodes[i].y() - y) - 0.2 * side * resp.nodes[i].x() <
                           std::abs(resp.nodes[best].y() - y) - 0.2 * side * resp.nodes[best].x()))
        best = i;
    if (best < 0) throw pipeline::bad_input("respirator", "rim has no node on one side of the symmetry plane");
    return Eigen::Vector3d(resp.nodes[best] + shift);
  };
  *top = {pick(ymid + q, 1), pick(ymid + q, -1)};
  *bottom = {pick(ymid - q, 1), pick(ymid - q, -1)};
}

double lay_strap(const FeModel& head, const internal::TriangleTree& tree, const Attach& a, double back_y,
                 const StrapOptions& opt, const std::string& name, FeModel* out) {
  // Point on the back of the head (sagittal plane, height back_y): the rear-most skin node there.
  Eigen::Vector3d back(0, back_y, 1e300);
  for (const auto& p : head.nodes)
    if (std::abs(p.x()) < 8 && std::abs(p.y() - back_y) < 6 && p.z() < back.z()) back = p;
  if (back.z() > 1e299) throw pipeline::bad_input("head", name + ": no skin at the back of the head at y = " + std::to_string(back_y));
  const Eigen::Vector3d mid = 0.5 * (a.left + a.right), o = 0.5 * (mid + back);
  const Eigen::Vector3d u = (a.left - a.right).normalized();
  Eigen::Vector3d w = back - o;
  w = (w - w.dot(u) * u).normalized();
  const Eigen::Vector3d nrm = u.cross(w).normalized();
  const double lift = opt.gap_mm + 0.5 * opt.thickness_mm;
  auto angle = [&](const Eigen::Vector3d& p) { return std::atan2((p - o).dot(w), (p - o).dot(u)); };
  double tl = angle(a.left), tr = angle(a.right);
  if (tl > M_PI / 2) tl -= 2 * M_PI;
  if (tr < M_PI / 2) tr += 2 * M_PI;
  // Outline from the left attachment over the back to the right one, lifted off the skin.
  std::vector<Eigen::Vector3d> path;
  for (double t = tl; t <= tr; t += M_PI / 720) {
    const Eigen::Vector3d d = std::cos(t) * u + std::sin(t) * w;
    const double r = tree.farthest_hit(o, d);
    if (r > 0) path.push_back(o + (r + lift) * d);
  }
  if (path.size() < 10) throw pipeline::bad_input("head", name + ": the strap plane misses the head");
  // A taut strap bridges the concave places of the outline (ears, the nape): keep its convex
  // chain (Graham scan; the outline is star-shaped about o, points in increasing angle t, i.e.
  // counter-clockwise about nrm = u × w, so a convex corner turns left), then
  // resample the straight spans every 1 mm. Folding the band into hollows made it cross itself.
  {
    auto cross2 = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& q) {
      return ((b - a).cross(q - b)).dot(nrm);
    };
    std::vector<Eigen::Vector3d> hull;
    for (const auto& q : path) {
      while (hull.size() >= 2 && cross2(hull[hull.size() - 2], hull.back(), q) <= 0) hull.pop_back();
      hull.push_back(q);
    }
    std::vector<Eigen::Vector3d> dense;
    for (std::size_t i = 0; i + 1 < hull.size(); ++i) {
      const int m = std::max(1, int(std::ceil((hull[i + 1] - hull[i]).norm() / 1.0)));
      for (int j = 0; j < m; ++j) dense.push_back(hull[i] + (hull[i + 1] - hull[i]) * (double(j) / m));
    }
    dense.push_back(hull.back());
    path = dense;
  }
  std::vector<double> s(path.size(), 0.0);
  for (std::size_t i = 1; i < path.size(); ++i) s[i] = s[i - 1] + (path[i] - path[i - 1]).norm();
  std::size_t ib = 0;
  for (std::size_t i = 0; i < path.size(); ++i)
    if ((path[i] - back).norm() < (path[ib] - back).norm()) ib = i;
  const double s0 = s[ib] - 0.5 * opt.length_mm, s1 = s[ib] + 0.5 * opt.length_mm;
  if (s0 < 0 || s1 > s.back())
    throw pipeline::bad_input("straps", name + ": length " + std::to_string(opt.length_mm) + " mm exceeds the head outline between its attachment points (" + std::to_string(s.back()) + " mm)");
  const int n = std::max(2, int(std::ceil(opt.length_mm / opt.element_mm)));
  const int base = int(out->nodes.size());
  // Nodes: n+1 stations × 3 across the width (centre and both edges).
  std::size_t k = 0;
  for (int i = 0; i <= n; ++i) {
    const double si = s0 + (s1 - s0) * i / n;
    while (k + 2 < s.size() && s[k + 1] < si) ++k;
    const double f = (si - s[k]) / std::max(1e-12, s[k + 1] - s[k]);
    const Eigen::Vector3d c = path[k] + f * (path[k + 1] - path[k]);
    // Across the band: in the skin's tangent plane (normal of the closest skin point × the strap
    // direction), so where the strap plane cuts the surface obliquely the band lies on the skin
    // instead of digging one edge into it (pushing such edges out folded the band).
    Eigen::Vector3d cp, nn;
    tree.signed_distance(c, &cp, &nn);
    Eigen::Vector3d across = nn.cross(path[k + 1] - path[k]);
    if (across.norm() < 1e-9 * (path[k + 1] - path[k]).norm() || !across.allFinite()) across = nrm;
    across.normalize();
    if (across.dot(nrm) < 0) across = -across;
    for (int j = -1; j <= 1; ++j) out->nodes.push_back(c + j * 0.5 * opt.width_mm * across);
  }
  // Push nodes that came closer than the lift (curvature across the width) out along the normal.
  for (int pass = 0; pass < 4; ++pass)
    for (std::size_t i = base; i < out->nodes.size(); ++i) {
      Eigen::Vector3d cp, nn;
      const double d = tree.signed_distance(out->nodes[i], &cp, &nn);
      if (d < lift) out->nodes[i] = cp + lift * (d < 0 ? -(out->nodes[i] - cp).normalized() : (out->nodes[i] - cp).normalized());
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
  internal::TriangleTree tree(head.nodes, head_surface(head));
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
  }
  r.top_length = lay_strap(head, tree, top, top_y, opt, "strap_top", &out);
  const int bottom_base = int(out.nodes.size());
  r.bottom_length = lay_strap(head, tree, bottom, lm.at("menton").y() - opt.bottom_below_menton_mm, opt, "strap_bottom", &out);
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
      throw pipeline::algorithm_failed("straps", std::to_string(push.size()) + " strap nodes still on faces crossing the skin, e.g. near (" +
                                                     std::to_string(q.x()) + ", " + std::to_string(q.y()) + ", " + std::to_string(q.z()) + ") mm");
    }
    for (int v : push) {
      Eigen::Vector3d cp;
      tree.signed_distance(out.nodes[v], &cp);
      out.nodes[v] += (out.nodes[v] - cp).normalized();
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
      for (int v : b.conn) r.min_gap = std::min(r.min_gap, tree.signed_distance(out.nodes[v]));
    }
  if (report) *report = r;
  return out;
}

}  // namespace meshing
