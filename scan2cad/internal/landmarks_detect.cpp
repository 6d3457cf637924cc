// scan2cad::detect_landmarks and check_landmarks_on_surface (declared in landmarks.h).
//
// Why by hand: no library detects facial landmarks on a mesh. The geometry is simple and
// written here: the midline profile is the mesh's section by x = 0; lateral landmarks are
// "soft" extremes (area-weighted soft-argmax over face centroids), which stay put under
// re-meshing where a single extreme vertex would jump. CGAL's AABB tree projects points.
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "pipeline/error.h"
#include "scan2cad/landmarks.h"

namespace scan2cad {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using pipeline::SurfaceMesh;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel, CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>>>;
constexpr double inf = std::numeric_limits<double>::infinity();

Vector3d E(const pipeline::Point& p) { return {p.x(), p.y(), p.z()}; }

struct Faces {  // one entry per triangle: centroid, outward unit normal, area
  std::vector<Vector3d> c, n;
  std::vector<double> a;
};

Faces face_data(const SurfaceMesh& m) {
  Faces f;
  Vector3d centre = Vector3d::Zero();
  for (auto v : m.vertices()) centre += E(m.point(v));
  centre /= double(std::max<std::size_t>(1, m.number_of_vertices()));
  double flux = 0.0;
  for (auto fi : m.faces()) {
    auto h = m.halfedge(fi);
    const Vector3d p = E(m.point(m.source(h))), q = E(m.point(m.target(h))), r = E(m.point(m.target(m.next(h))));
    const Vector3d cr = (q - p).cross(r - p);
    const double area = 0.5 * cr.norm();
    if (!(area > 0.0)) continue;
    f.c.push_back((p + q + r) / 3.0);
    f.n.push_back(cr.normalized());
    f.a.push_back(area);
    flux += (f.c.back() - centre).dot(f.n.back()) * area;
  }
  if (flux < 0.0)  // inward-oriented mesh: flip so that normals point out of the head
    for (auto& n : f.n) n = -n;
  return f;
}

/// Area-weighted soft-argmax of `score` over the faces that `keep` accepts: the weighted mean
/// centroid with weights area·exp((score − max)/tau)·membership (membership in [0, 1], 1 if
/// not given: a soft selection whose edge does not jump with the facets). Returns false if no
/// face is kept.
bool soft_argmax(const Faces& f, const std::function<bool(std::size_t)>& keep,
                 const std::function<double(std::size_t)>& score, double tau, Vector3d& out, std::size_t* count = nullptr,
                 const std::function<double(std::size_t)>& membership = nullptr) {
  double top = -inf;
  std::size_t k = 0;
  for (std::size_t i = 0; i < f.c.size(); ++i)
    if (keep(i)) top = std::max(top, score(i)), ++k;
  if (count) *count = k;
  if (k == 0) return false;
  Vector3d s = Vector3d::Zero();
  double w = 0.0;
  for (std::size_t i = 0; i < f.c.size(); ++i)
    if (keep(i)) {
      const double wi = f.a[i] * std::exp((score(i) - top) / tau) * (membership ? membership(i) : 1.0);
      s += wi * f.c[i], w += wi;
    }
  if (!(w > 0.0)) return false;
  out = s / w;
  return true;
}

/// Front profile z = f(y) of the mesh section by x = 0, on a 0.5 mm grid in y.
struct Profile {
  double y0 = 0.0, dy = 0.5;
  std::vector<double> z;  // −inf where the section has no point
  double y(std::size_t i) const { return y0 + dy * double(i); }
  std::size_t index(double yy) const {
    return std::size_t(std::clamp((yy - y0) / dy, 0.0, double(z.size() - 1)));
  }
  /// Index of the max (sign +1) or min (−1) of z over [ya, yb]; z.size() if none.
  std::size_t extreme(double ya, double yb, int sign) const {
    std::size_t best = z.size();
    for (std::size_t i = index(ya); i <= index(yb); ++i)
      if (std::isfinite(z[i]) && (best == z.size() || sign * z[i] > sign * z[best])) best = i;
    return best;
  }
  /// Vertex of a least-squares parabola through the profile within ±w mm of index i: a
  /// sub-grid extreme that does not jump with the mesh.
  Vector2d refine(std::size_t i, double w) const {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (std::size_t k = index(y(i) - w); k <= index(y(i) + w); ++k) {
      if (!std::isfinite(z[k])) continue;
      const double t = y(k) - y(i);
      const Eigen::Vector3d r(1.0, t, t * t);
      A += r * r.transpose(), b += r * z[k];
    }
    const Eigen::Vector3d c = A.ldlt().solve(b);
    if (!c.allFinite() || std::abs(c[2]) < 1e-9) return {y(i), z[i]};
    const double t = std::clamp(-c[1] / (2.0 * c[2]), -w, w);
    return {y(i) + t, c[0] + c[1] * t + c[2] * t * t};
  }
};

/// Section of the mesh by x = 0: segments in (y, z); also fills the front profile.
std::vector<std::pair<Vector2d, Vector2d>> midline(const SurfaceMesh& m, Profile& prof) {
  std::vector<std::pair<Vector2d, Vector2d>> segs;
  double lo = inf, hi = -inf;
  for (auto fi : m.faces()) {
    std::vector<Vector2d> pts;
    for (auto h : halfedges_around_face(m.halfedge(fi), m)) {
      const Vector3d a = E(m.point(m.source(h))), b = E(m.point(m.target(h)));
      if ((a.x() < 0.0) != (b.x() < 0.0)) {
        const double u = a.x() / (a.x() - b.x());
        const Vector3d p = a + u * (b - a);
        pts.emplace_back(p.y(), p.z());
      }
    }
    if (pts.size() == 2) {
      segs.push_back({pts[0], pts[1]});
      lo = std::min({lo, pts[0].x(), pts[1].x()}), hi = std::max({hi, pts[0].x(), pts[1].x()});
    }
  }
  if (segs.size() < 30) throw pipeline::algorithm_failed("head", "no midline section at x = 0 (is the head aligned?)");
  prof.y0 = std::floor(lo);
  prof.z.assign(std::size_t((hi - prof.y0) / prof.dy) + 1, -inf);
  for (const auto& [p, q] : segs) {
    const double ya = std::min(p.x(), q.x()), yb = std::max(p.x(), q.x());
    for (std::size_t i = prof.index(ya); i <= prof.index(yb); ++i) {
      const double yy = prof.y(i);
      if (yy < ya || yy > yb) continue;
      const double t = yb > ya ? (yy - p.x()) / (q.x() - p.x()) : 0.0;
      prof.z[i] = std::max(prof.z[i], p.y() + t * (q.y() - p.y()));
    }
  }
  return segs;
}

Landmark at(const Vector3d& p, double conf) { return {p, std::clamp(conf, 0.0, 1.0)}; }

}  // namespace

Landmarks detect_landmarks(const SurfaceMesh& head) {
  Landmarks L;
  Profile prof;
  const auto segs = midline(head, prof);
  const Faces F = face_data(head);

  // 1. Pronasale: the highest point of the front profile (nose tip), parabola-refined.
  const std::size_t ip = prof.extreme(prof.y(0), prof.y(prof.z.size() - 1), +1);
  const Vector2d prn = prof.refine(ip, 3.0);
  const std::size_t i_gl = prof.extreme(prn.x() + 30.0, prn.x() + 90.0, +1);  // glabella (forehead)
  if (i_gl == prof.z.size()) throw pipeline::algorithm_failed("head", "no forehead above the nose tip");
  const double around = std::max(prof.z[prof.extreme(prn.x() + 40, prn.x() + 45, +1) % prof.z.size()],
                                 prof.z[prof.extreme(prn.x() - 45, prn.x() - 40, +1) % prof.z.size()]);
  L.points["pronasale"] = at({0.0, prn.x(), prn.y()}, (prn.y() - around) / 15.0);

  // 2. Sellion: deepest point of the profile between the nose tip and the glabella.
  const std::size_t is = prof.extreme(prn.x() + 10.0, prof.y(i_gl), -1);
  const Vector2d sel = prof.refine(is, 8.0);
  L.points["sellion"] = at({0.0, sel.x(), sel.y()}, (prof.z[i_gl] - sel.y()) / 3.0);

  // 4. Menton: lowest point of the chin, taken as the support point of the midline section in
  //    the direction 30° forward of straight down, among section points of the chin region
  //    (40–130 mm below the nose tip, at most 60 mm behind it; the neck lies further back).
  //    The submental surface faces ~10–20° forward of down, so the support stays on the chin.
  const Vector2d dmen(-std::cos(M_PI / 6), std::sin(M_PI / 6));
  Vector2d men_sum(0, 0);
  double wsum = 0.0, smax = -inf;
  std::vector<std::pair<Vector2d, double>> chin;  // section sampled every ≤ 0.5 mm, with length
  for (const auto& [p, q] : segs) {
    const int n = std::max(1, int(std::ceil((q - p).norm() / 0.5)));
    for (int k = 0; k < n; ++k) {
      const Vector2d s = p + (q - p) * ((k + 0.5) / n);
      if (s.x() < prn.x() - 130 || s.x() > prn.x() - 40 || s.y() < prn.y() - 60) continue;
      chin.push_back({s, (q - p).norm() / n});
      smax = std::max(smax, s.dot(dmen));
    }
  }
  if (chin.empty()) throw pipeline::algorithm_failed("head", "no chin below the nose tip");
  for (const auto& [s, len] : chin) {
    const double w = len * std::exp((s.dot(dmen) - smax) / 0.5);
    men_sum += w * s, wsum += w;
  }
  const Vector2d men = men_sum / wsum;
  L.points["menton"] = at({0.0, men.x(), men.y()}, 0.8);

  // 5. Each side (s = +1 left, −1 right).
  for (int s : {+1, -1}) {
    const std::string side = s > 0 ? "_left" : "_right";
    // Tragion: the ear sticks out of the side of the head 80–190 mm behind the nose tip. Ear
    // = faces within 10 mm of the most lateral point there; tragion = its front edge
    // (soft-max z) at the ear's mean height.
    auto ear_window = [&](std::size_t i) {
      const Vector3d& c = F.c[i];
      return s * c.x() > 20 && c.y() > prn.x() - 40 && c.y() < sel.x() + 25 && c.z() < prn.y() - 80 &&
             c.z() > prn.y() - 190;
    };
    Vector3d ear_out;
    if (!soft_argmax(F, ear_window, [&](std::size_t i) { return s * F.c[i].x(); }, 1.0, ear_out))
      throw pipeline::algorithm_failed("head", "no ear region on side " + side.substr(1));
    const double xe = s * ear_out.x();
    double ym = 0.0, am = 0.0;
    for (std::size_t i = 0; i < F.c.size(); ++i)
      if (ear_window(i) && s * F.c[i].x() > xe - 10) ym += F.a[i] * F.c[i].y(), am += F.a[i];
    ym /= am;
    Vector3d tr;
    soft_argmax(F, [&](std::size_t i) { return ear_window(i) && s * F.c[i].x() > xe - 10 && std::abs(F.c[i].y() - ym) < 8; },
                [&](std::size_t i) { return F.c[i].z(); }, 1.5, tr);
    // Zygion: most lateral point of the face in front of the ear, at cheekbone height
    // (0–40 mm below the sellion), behind the eyes (≥ 40 mm behind the nose tip).
    Vector3d zy;
    std::size_t nz = 0;
    if (!soft_argmax(F, [&](std::size_t i) {
          const Vector3d& c = F.c[i];
          return s * c.x() > 20 && c.y() < sel.x() && c.y() > sel.x() - 40 && c.z() > tr.z() + 15 && c.z() < prn.y() - 40;
        }, [&](std::size_t i) { return s * F.c[i].x(); }, 1.0, zy, &nz))
      throw pipeline::algorithm_failed("head", "no cheek region on side " + side.substr(1));
    // Gonion: jaw angle = the up-and-back corner of the down-facing underside of the jaw, off
    // the midline, 15 mm or more below the nose tip (below the ear lobe) and in front of the ear.
    // "Down-facing" is a soft membership (0 at n_y = -0.3, 1 at n_y = -0.7, smoothstep): the
    // corner sits where the underside turns to the neck, where a hard n_y cut decides the
    // point facet by facet (still 1.06 mm on gonion_right under re-meshing, against 1 mm).
    Vector3d go;
    std::size_t ng = 0;
    const auto down_facing = [&](std::size_t i) {
      const double t = std::clamp((-F.n[i].y() - 0.3) / 0.4, 0.0, 1.0);
      return t * t * (3.0 - 2.0 * t);
    };
    if (!soft_argmax(F, [&](std::size_t i) {
          const Vector3d& c = F.c[i];
          return F.n[i].y() < -0.3 && s * c.x() > 25 && c.y() > men.x() - 20 && c.y() < prn.x() - 15 &&
                 c.z() > tr.z() - 5 && c.z() < men.y();
        }, [&](std::size_t i) { return (F.c[i].y() - F.c[i].z()) / std::sqrt(2.0); }, 3.0, go, &ng, down_facing))
      throw pipeline::algorithm_failed("head", "no jaw underside on side " + side.substr(1));
    const double ear_prominence = xe - s * zy.x();  // how far the ear sticks out [mm]
    L.points["tragion" + side] = at(tr, 0.3 + ear_prominence / 20.0);
    L.points["zygion" + side] = at(zy, 0.8);
    L.points["gonion" + side] = at(go, ng >= 20 ? 0.6 : 0.3);
  }

  // 6. Lateral points onto the surface; confidence drops with left/right mismatch.
  Tree tree(faces(head).first, faces(head).second, head);
  tree.accelerate_distance_queries();
  for (auto& [name, p] : L.points) {
    p.position = E(tree.closest_point(pipeline::Point(p.position.x(), p.position.y(), p.position.z())));
    if (name.find("_left") != std::string::npos) {
      auto& r = L.points[name.substr(0, name.size() - 5) + "_right"];
      r.position = E(tree.closest_point(pipeline::Point(r.position.x(), r.position.y(), r.position.z())));
      const Vector3d mirror(-r.position.x(), r.position.y(), r.position.z());
      const double k = std::exp(-(p.position - mirror).norm() / 10.0);
      p.confidence *= k, r.confidence *= k;
    }
  }
  return L;
}

void check_landmarks_on_surface(const Landmarks& l, const SurfaceMesh& head, const std::string& what, double tol) {
  Tree tree(faces(head).first, faces(head).second, head);
  tree.accelerate_distance_queries();
  for (const auto& [name, p] : l.points) {
    const double d = std::sqrt(tree.squared_distance(pipeline::Point(p.position.x(), p.position.y(), p.position.z())));
    if (d > tol)
      throw pipeline::bad_input(what, "landmark " + name + " is " + std::to_string(d) + " mm from the head surface, expected <= " +
                                          std::to_string(tol) + " mm (same frame as the aligned head?)");
  }
}

}  // namespace scan2cad
