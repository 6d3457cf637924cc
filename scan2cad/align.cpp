// Head and respirator alignment into the paper's frame; see align.h.
#include "scan2cad/align.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "pipeline/error.h"
#include "pipeline/read_json.h"
#include "scan2cad/internal/align_symmetry.h"

namespace scan2cad {
namespace {

using Eigen::Vector3d;
using internal::SurfaceSamples;

/// Surface samples (and their seed) of the in-plane axes and the face search.
constexpr std::size_t axes_samples = 20000;
constexpr unsigned axes_seed = 11;

/// Extent of `values` between the 2nd and 98th percentiles (robust to stray samples).
double robust_range(std::vector<double> v) {
  if (v.size() < 10) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() * 98 / 100] - v[v.size() * 2 / 100];
}

/// Lateral width of the cap of samples within `band` of the extreme along `dir` [mm].
double cap_width(const SurfaceSamples& s, const internal::Plane& pl, const Vector3d& dir, double band) {
  double top = -std::numeric_limits<double>::infinity();
  for (const auto& p : s.p) top = std::max(top, p.dot(dir));
  double lo = 1e300, hi = -1e300;
  for (const auto& p : s.p)
    if (p.dot(dir) > top - band) lo = std::min(lo, pl.n.dot(p)), hi = std::max(hi, pl.n.dot(p));
  return hi - lo;
}

/// Support value max(p·dir) over the midline samples whose height (p − tip)·up is in [h0, h1].
double support(const std::vector<Vector3d>& mid, const Vector3d& tip, const Vector3d& up, double h0, double h1,
               const Vector3d& dir) {
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& p : mid) {
    const double h = (p - tip).dot(up);
    if (h >= h0 && h <= h1) best = std::max(best, p.dot(dir));
  }
  return best;
}

/// Principal axes of the surface within the symmetry plane: a the longer, b = n × a.
void in_plane_axes(const SurfaceSamples& s, const internal::Plane& pl, Vector3d& a, Vector3d& b) {
  Vector3d mean;
  Eigen::Matrix3d cov;
  internal::sample_moments(s, mean, cov);
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - pl.n * pl.n.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(P * cov * P);
  a = eig.eigenvectors().col(2).normalized();
  b = pl.n.cross(a).normalized();
}

/// Head: face direction z and up y in the symmetry plane (unit vectors, in-plane).
void head_axes(const SurfaceSamples& s, const internal::Plane& pl, const Vector3d& a, const Vector3d& b,
               Vector3d& y, Vector3d& z) {
  // 1. Rough face direction: the nose tip is a point-like extreme, so the cap within 10 mm of it
  //    is narrow laterally; the crown, occiput and the edge of a cut neck give wide caps.
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 72; ++k) {
    const double t = k * M_PI / 36.0;
    const Vector3d dir = std::cos(t) * a + std::sin(t) * b;
    const double w = cap_width(s, pl, dir, 10.0);
    if (w < best) best = w, z = dir;
  }
  std::vector<Vector3d> mid;  // samples near the sagittal plane
  for (const auto& p : s.p)
    if (std::abs(pl.n.dot(p) - pl.d) < 8.0) mid.push_back(p);
  if (mid.size() < 20) throw pipeline::algorithm_failed("head", "too few surface points near the symmetry plane");
  auto nose_tip = [&](const Vector3d& dir) {
    Vector3d tip = mid.front();
    for (const auto& p : mid)
      if (p.dot(dir) > tip.dot(dir)) tip = p;
    return tip;
  };
  // 2. Pitch: the face looks perpendicular to its profile line, the common tangent of the
  //    forehead (45–120 mm above the nose tip) and the lips/chin (30–110 mm below), which leaves
  //    out the nose. Iterated so that the bands are measured in the final frame.
  auto pitch = [&](Vector3d& yy, Vector3d& zz) {
    for (int it = 0; it < 10; ++it) {
      const Vector3d tip = nose_tip(zz);
      auto gap = [&](double t) {  // forehead minus chin support along z rotated by t toward y
        const Vector3d d = std::cos(t) * zz + std::sin(t) * yy;
        return support(mid, tip, yy, 45.0, 120.0, d) - support(mid, tip, yy, -110.0, -30.0, d);
      };
      double lo = -0.7, hi = 0.7;  // ±40°: gap increases with t (forehead is above the chin)
      if (!(gap(lo) < 0.0 && gap(hi) > 0.0)) return false;
      for (int k = 0; k < 50; ++k) {
        const double m = 0.5 * (lo + hi);
        (gap(m) > 0.0 ? hi : lo) = m;
      }
      const double t = 0.5 * (lo + hi);
      const Vector3d z2 = (std::cos(t) * zz + std::sin(t) * yy).normalized();
      yy = (std::cos(t) * yy - std::sin(t) * zz).normalized();
      zz = z2;
      if (std::abs(t) < 1e-6) break;
    }
    return true;
  };
  // 3. Up: try both senses; in the right one, 70–100 mm above the nose tip the midline front
  //    profile is the forehead (forward), as far below it the neck (far behind the tip).
  double best_margin = -std::numeric_limits<double>::infinity();
  const Vector3d z0 = z;
  for (int sgn : {+1, -1}) {
    Vector3d yy = sgn * pl.n.cross(z0).normalized(), zz = z0;
    if (!pitch(yy, zz)) continue;
    const Vector3d tip = nose_tip(zz);
    const double margin = support(mid, tip, yy, 70.0, 100.0, zz) - support(mid, tip, -yy, 70.0, 100.0, zz);
    if (std::isfinite(margin) && margin > best_margin) best_margin = margin, y = yy, z = zz;
  }
  if (!(best_margin > 0.0))
    throw pipeline::algorithm_failed("head", "cannot tell up from down: no forehead-chin profile line found near the nose");
}

/// Respirator: y along the long in-plane axis (nose end = narrower, +y), z along the short one
/// with the open, wider side of the cup toward −z.
void respirator_axes(const pipeline::SurfaceMesh& mesh, const SurfaceSamples& s, const internal::Plane& pl,
                     const Vector3d& a, const Vector3d& b, Vector3d& y, Vector3d& z) {
  auto end_spread = [&](const Vector3d& axis, bool high, double frac, bool area) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& p : s.p) lo = std::min(lo, p.dot(axis)), hi = std::max(hi, p.dot(axis));
    const Vector3d other = axis.cross(pl.n).normalized();
    std::vector<double> xs, os;
    for (const auto& p : s.p) {
      const double t = (p.dot(axis) - lo) / (hi - lo);
      if (high ? t > 1.0 - frac : t < frac) xs.push_back(pl.n.dot(p)), os.push_back(p.dot(other));
    }
    return area ? robust_range(xs) * robust_range(os) : robust_range(xs);
  };
  z = end_spread(b, true, 0.2, true) > end_spread(b, false, 0.2, true) ? Vector3d(-b) : b;
  // An open cup says which side is open: its rim, the border of the mesh, lies on that side of
  // the surface's centroid (19-21 mm along b on the generated cups). The wider end above is the
  // guess for a closed shell; on a clean cup's points, whose rim band came out sparse, it chose
  // the dome's end and the cup was placed inside out (sweep K).
  Vector3d rim_sum = Vector3d::Zero(), centroid_sum = Vector3d::Zero();
  double rim_mm = 0, area_mm2 = 0;
  auto at = [&](pipeline::SurfaceMesh::Vertex_index v) {
    const auto& p = mesh.point(v);
    return Vector3d(p.x(), p.y(), p.z());
  };
  for (auto h : mesh.halfedges())
    if (mesh.is_border(h)) {
      const Vector3d p = at(mesh.source(h)), q = at(mesh.target(h));
      rim_sum += (p - q).norm() * 0.5 * (p + q), rim_mm += (p - q).norm();
    }
  for (auto f : mesh.faces()) {
    const auto h = mesh.halfedge(f);
    const Vector3d p = at(mesh.source(h)), q = at(mesh.target(h)), r = at(mesh.target(mesh.next(h)));
    const double area = 0.5 * (q - p).cross(r - p).norm();
    centroid_sum += area * (p + q + r) / 3.0, area_mm2 += area;
  }
  constexpr double min_rim_offset_mm = 5;
  if (rim_mm > 0 && area_mm2 > 0) {
    const double rim_to_centroid = (centroid_sum / area_mm2 - rim_sum / rim_mm).dot(b);
    if (std::abs(rim_to_centroid) > min_rim_offset_mm) z = rim_to_centroid > 0 ? b : Vector3d(-b);
  }
  y = end_spread(a, true, 0.25, false) < end_spread(a, false, 0.25, false) ? a : Vector3d(-a);
  // Pitch from the rim: in the symmetry plane the shell's section is a U (two bands for a frame
  // open at both ends) whose tips toward the face side (-z) are the rim at the nose bridge and
  // at the chin. y runs from the chin tip to the nose tip, so the nose-chin line of the rim is
  // vertical, as on a face aligned by `align --kind head`. (The long axis alone tilts the
  // generated cups by ~12 deg: assembled, their rim then stands off the cheeks.)
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& p : s.p) lo = std::min(lo, p.dot(y)), hi = std::max(hi, p.dot(y));
  const double mid = 0.5 * (lo + hi), band_mm = 1.5;
  const Vector3d* tip[2] = {nullptr, nullptr};  // chin, nose
  for (const auto& p : s.p) {
    if (std::abs(pl.n.dot(p) - pl.d) > band_mm) continue;
    const int k = p.dot(y) > mid ? 1 : 0;
    if (!tip[k] || p.dot(z) < tip[k]->dot(z)) tip[k] = &p;
  }
  if (!tip[0] || !tip[1]) return;
  Vector3d rim_y = *tip[1] - *tip[0];
  rim_y -= pl.n.dot(rim_y) * pl.n;
  if (rim_y.norm() < 0.25 * (hi - lo) || rim_y.normalized().dot(y) < std::cos(45.0 * M_PI / 180.0)) return;
  y = rim_y.normalized();
  z = (z - z.dot(y) * y).normalized();
}

}  // namespace

AlignKind parse_align_kind(const std::string& name) {
  if (name == "head") return AlignKind::head;
  if (name == "respirator") return AlignKind::respirator;
  throw pipeline::Error(pipeline::ErrorKind::usage, "--kind: got '" + name + "', expected head or respirator");
}

AlignResult align(const pipeline::SurfaceMesh& mesh, const AlignOptions& opt) {
  if (mesh.number_of_faces() == 0) throw pipeline::bad_input("surface", "no faces");
  // 1. Symmetry plane → lateral axis.
  const auto sym = internal::find_symmetry_plane(mesh, std::size_t(opt.samples));
  const internal::Plane& pl = sym.plane;
  // Most of a whole head or cup matches its mirror image: 99-100 % on the 30 cases' surfaces, over
  // 80 % on the real respirator parts. A head with one side cut away (57 %) and cups cut in half
  // or above the chin (65-69 %) were aligned 176 deg off or tilted, with exit 0 (sweeps J, K).
  constexpr double min_symmetry_inliers = 0.75;
  if (!(sym.inlier_fraction >= min_symmetry_inliers))
    throw pipeline::algorithm_failed(
        opt.kind == AlignKind::head ? "head" : "respirator",
        "only " + std::to_string(int(std::lround(100 * sym.inlier_fraction))) +
            " % of the surface matches its mirror image across the best symmetry plane (RMS " +
            pipeline::format_number(std::round(sym.rms_mm * 100) / 100) + " mm; a whole " +
            (opt.kind == AlignKind::head ? "head" : "cup") + " gives over 80 %): is a side of it missing or cut away? "
            "align finds the frame from the two sides' symmetry");
  // 2. In-plane principal axes of the surface.
  const SurfaceSamples s = internal::sample_surface(mesh, axes_samples, axes_seed);
  Vector3d a, b;
  in_plane_axes(s, pl, a, b);
  Vector3d y = Vector3d::Zero(), z = Vector3d::Zero();  // both set by the axes functions (or they throw)
  if (opt.kind == AlignKind::head)
    head_axes(s, pl, a, b, y, z);
  else
    respirator_axes(mesh, s, pl, a, b, y, z);
  // 3. Right-handed frame and origin.
  const Vector3d x = y.cross(z);
  Eigen::Matrix3d R;
  R.row(0) = x.transpose();
  R.row(1) = y.transpose();
  R.row(2) = z.transpose();
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (auto v : mesh.vertices()) {
    const auto& q = mesh.point(v);
    const Vector3d r = R * Vector3d(q.x(), q.y(), q.z());
    for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], r[k + 1]), hi[k] = std::max(hi[k], r[k + 1]);
  }
  AlignResult res;
  res.transform.block<3, 3>(0, 0) = R;
  res.transform(0, 3) = -x.dot(pl.d * pl.n);
  res.transform(1, 3) = -0.5 * (lo[0] + hi[0]);
  res.transform(2, 3) = -0.5 * (lo[1] + hi[1]);
  res.symmetry_rms_mm = sym.rms_mm;
  res.symmetry_inliers = sym.inlier_fraction;
  return res;
}

HeadFrameError head_frame_error(const pipeline::SurfaceMesh& head) {
  if (head.number_of_faces() == 0) throw pipeline::bad_input("surface", "no faces");
  HeadFrameError e;
  try {
    const Eigen::Matrix4d T = align(head, AlignOptions{}).transform;
    e.realigned = true;
    e.turn_deg = std::acos(std::clamp((T.block<3, 3>(0, 0).trace() - 1) / 2, -1.0, 1.0)) * 180.0 / M_PI;
    e.shift_mm = T.block<3, 1>(0, 3).norm();
  } catch (const pipeline::Error& err) {  // no symmetry plane or face: the tests below
    if (err.kind != pipeline::ErrorKind::algorithm) throw;
  }
  const SurfaceSamples s = internal::sample_surface(head, axes_samples, axes_seed);
  // Mirror test: a plane other than x = 0 (a turned or shifted head) leaves mirrored samples
  // tens of mm off the surface; the median ignores asymmetric ears and scan holes.
  std::vector<Vector3d> mirrored;
  for (std::size_t i = 0; i < s.p.size() && mirrored.size() < 2000; ++i) mirrored.emplace_back(-s.p[i].x(), s.p[i].y(), s.p[i].z());
  std::vector<double> d = internal::capped_distances(head, mirrored, 50.0);
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  e.mirror_mm = d[d.size() / 2];
  // Face and up as align finds them in the plane x = 0.
  const internal::Plane pl;  // x = 0
  Vector3d a, b, y, z;
  in_plane_axes(s, pl, a, b);
  try {
    head_axes(s, pl, a, b, y, z);
  } catch (const pipeline::Error& err) {  // no nose, no forehead-chin profile in this plane
    if (err.kind != pipeline::ErrorKind::algorithm) throw;
    return e;
  }
  auto angle_deg = [](const Vector3d& u, const Vector3d& v) {
    return std::acos(std::clamp(u.normalized().dot(v), -1.0, 1.0)) * 180.0 / M_PI;
  };
  e.face_found = true;
  e.face_deg = angle_deg(z, Vector3d::UnitZ());
  e.up_deg = angle_deg(y, Vector3d::UnitY());
  return e;
}

void require_head_frame(const HeadFrameError& e) {
  char why[200];
  if (e.realigned) {
    if (e.turn_deg <= head_frame_max_turn_deg && e.shift_mm <= head_frame_max_shift_mm) return;
    std::snprintf(why, sizeof why, "align would turn it by %.1f deg and move it by %.1f mm", e.turn_deg, e.shift_mm);
    throw pipeline::Error(pipeline::ErrorKind::bad_input,
                          std::string("the head is not in the head frame (") + why + "): align it first (align --kind head)");
  }
  const bool angles_ok = !e.face_found || (e.face_deg <= head_frame_max_angle_deg && e.up_deg <= head_frame_max_angle_deg);
  if (e.mirror_mm <= head_frame_max_mirror_mm && angles_ok) return;
  if (e.face_found)
    std::snprintf(why, sizeof why, "face direction %.0f deg from +z, up %.0f deg from +y, its mirror image in x = 0 %.1f mm off it",
                  e.face_deg, e.up_deg, e.mirror_mm);
  else
    std::snprintf(why, sizeof why, "no face found in the plane x = 0, its mirror image in x = 0 %.1f mm off it", e.mirror_mm);
  throw pipeline::Error(pipeline::ErrorKind::bad_input,
                        std::string("the head is not in the head frame (") + why + "): align it first (align --kind head)");
}

void require_head_frame(const pipeline::SurfaceMesh& head) { require_head_frame(head_frame_error(head)); }

void apply_transform(pipeline::SurfaceMesh& mesh, const Eigen::Matrix4d& T) {
  for (auto v : mesh.vertices()) {
    const auto& q = mesh.point(v);
    const Eigen::Vector4d r = T * Eigen::Vector4d(q.x(), q.y(), q.z(), 1.0);
    mesh.point(v) = pipeline::Point(r[0], r[1], r[2]);
  }
}

std::string align_json(const AlignResult& r, AlignKind kind, double unit_scale_to_mm) {
  nlohmann::json j;
  j["kind"] = kind == AlignKind::head ? "head" : "respirator";
  j["frame"] = "x lateral (+x = subject's left), y up, z out of the face; mm";
  j["origin"] = "x = 0 on the symmetry plane; y, z = 0 at the centre of the aligned bounding box";
  j["unit_scale_to_mm"] = unit_scale_to_mm;
  j["matrix_applies_to"] = "input coordinates after scaling to mm, as column vectors [x y z 1]";
  for (int i = 0; i < 4; ++i) j["matrix"].push_back({r.transform(i, 0), r.transform(i, 1), r.transform(i, 2), r.transform(i, 3)});
  j["symmetry_rms_mm"] = r.symmetry_rms_mm;
  j["symmetry_inliers"] = r.symmetry_inliers;
  return j.dump(2) + "\n";
}

}  // namespace scan2cad
