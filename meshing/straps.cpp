// make_straps: strap centre lines follow the head outline in the plane through the attachment
// points and a point on the back of the head (hand-written: a planar path on a surface; the ray
// casts and distances are CGAL's AABB tree).
#include "meshing/straps.h"

#include <Eigen/Geometry>

#include <cmath>

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
    for (int j = -1; j <= 1; ++j) out->nodes.push_back(c + j * 0.5 * opt.width_mm * nrm);
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
  r.top_length = lay_strap(head, tree, top, lm.at("sellion").y() + opt.top_above_sellion_mm, opt, "strap_top", &out);
  r.bottom_length = lay_strap(head, tree, bottom, lm.at("menton").y() - opt.bottom_below_menton_mm, opt, "strap_bottom", &out);
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
