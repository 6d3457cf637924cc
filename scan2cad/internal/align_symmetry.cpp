// Reflective-symmetry plane detection; see align_symmetry.h.
#include "scan2cad/internal/align_symmetry.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "pipeline/error.h"

namespace scan2cad::internal {
namespace {

using pipeline::SurfaceMesh;
// The triangles are cached in the primitives (CacheDatum): the tree then reads no mesh
// connectivity during queries, which on a mesh read from a shuffled soup made half the misses.
using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh, CGAL::Default, CGAL::Tag_true, CGAL::Tag_true>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel, Primitive>>;

Eigen::Vector3d to_eigen(const pipeline::Point& p) { return {p.x(), p.y(), p.z()}; }

Eigen::Vector3d reflect(const Eigen::Vector3d& p, const Plane& pl) {
  return p - 2.0 * (pl.n.dot(p) - pl.d) * pl.n;
}

/// A surface point matched to a query: the closest point and its face, or none within the cap.
struct Match {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();  ///< closest surface point [mm]
  Eigen::Vector3d n = Eigen::Vector3d::Zero();  ///< unit normal of its face
  double dist_mm = std::numeric_limits<double>::infinity();  ///< |query − c|; inf: nothing within the cap
  Tree::Point_and_primitive_id hint;           ///< c and its face in CGAL form, to seed the next query
  bool found() const { return std::isfinite(dist_mm); }
};

/// Closest points on the surface, with the normal of the face they lie on, when within a cap.
///
/// Why the cap: the symmetry search only uses min(distance, cap) (truncated score, ICP inlier
/// band tau <= cap), and reflected samples of a wrong candidate plane lie far from the surface,
/// where an unbounded AABB closest-point query visits much of the tree (it was ~40 % of the CPU
/// of a generated-head test). Bounded by the documented AABB_tree API: a box query
/// (any_intersected_primitive with an Iso_cuboid_3, a solid) first tells whether any face comes
/// within the cube circumscribing the cap ball; if one does, its projected point is a hint at
/// most sqrt(3) cap away for the exact closest_point_and_primitive(query, hint). The result is
/// the same closest point as an unbounded query; only its search is cut short.
struct Surface {
  const SurfaceMesh& mesh;
  Tree tree;
  SurfaceMesh::Property_map<pipeline::FaceIndex, pipeline::Vector> normals;
  explicit Surface(const SurfaceMesh& m) : mesh(m), tree(faces(m).first, faces(m).second, m) {
    tree.build();
    normals = const_cast<SurfaceMesh&>(m)
                  .add_property_map<pipeline::FaceIndex, pipeline::Vector>("f:align_normal", {0, 0, 0})
                  .first;
    CGAL::Polygon_mesh_processing::compute_face_normals(m, normals);
  }
  ~Surface() { const_cast<SurfaceMesh&>(mesh).remove_property_map(normals); }

  /// The closest surface point to q if it lies within cap_mm (m.found()), else m.dist_mm = inf.
  /// `previous` (a match of a nearby query, e.g. the last ICP iteration's) seeds the search.
  void closest_within(const Eigen::Vector3d& q, double cap_mm, Match& m, const Match* previous = nullptr) const {
    const pipeline::Point query(q.x(), q.y(), q.z());
    Tree::Point_and_primitive_id seed;
    if (previous && previous->found()) {
      seed = previous->hint;
    } else {
      auto box = [&](double r) {
        return tree.any_intersected_primitive(
            pipeline::Kernel::Iso_cuboid_3(q.x() - r, q.y() - r, q.z() - r, q.x() + r, q.y() + r, q.z() + r));
      };
      auto face = box(0.125 * cap_mm);
      if (!face) face = box(cap_mm);
      if (!face) {
        m.dist_mm = std::numeric_limits<double>::infinity();
        return;
      }
      const auto h = halfedge(*face, mesh);
      const pipeline::Kernel::Triangle_3 tri(mesh.point(source(h, mesh)), mesh.point(target(h, mesh)),
                                             mesh.point(target(next(h, mesh), mesh)));
      seed = {pipeline::Kernel().construct_projected_point_3_object()(tri, query), *face};
    }
    m.hint = tree.closest_point_and_primitive(query, seed);
    m.c = to_eigen(m.hint.first);
    m.dist_mm = (q - m.c).norm();
    if (m.dist_mm > cap_mm) {
      m.dist_mm = std::numeric_limits<double>::infinity();
      return;
    }
    const auto& v = normals[m.hint.second];
    m.n = {v.x(), v.y(), v.z()};
  }
};

/// Mean of min(distance, cap) of the reflected samples to the surface: lower is more symmetric.
double truncated_score(const Surface& s, const SurfaceSamples& smp, std::size_t stride, const Plane& pl,
                       double cap) {
  double sum = 0.0;
  std::size_t k = 0;
  Match m;
  for (std::size_t i = 0; i < smp.p.size(); i += stride, ++k) {
    s.closest_within(reflect(smp.p[i], pl), cap, m);
    sum += m.found() ? m.dist_mm : cap;
  }
  return sum / double(std::max<std::size_t>(k, 1));
}

/// When the ICP stops: after `max_iterations`, or once a step turns the plane by less than
/// `step_rad` and moves it by less than `step_mm` (from the 4th iteration on).
struct IcpStop {
  int max_iterations = 30;
  double step_rad = 1e-5;
  double step_mm = 1e-3;
};

/// Reflect-and-match ICP: Gauss-Newton on the point-to-plane distances of the reflected samples
/// to their closest surface points, over the plane's 2 rotation and 1 offset parameters.
SymmetryResult refine(const Surface& s, const SurfaceSamples& smp, Plane pl, double cap, const IcpStop& stop = {}) {
  const std::size_t N = smp.p.size();
  // Matches beyond the cap have dist = inf: tau <= cap leaves them out of the fit, as before.
  std::vector<Match> match(N);
  std::vector<double> dist(N);
  double tau = cap;
  for (int it = 0; it < stop.max_iterations; ++it) {
    for (std::size_t i = 0; i < N; ++i) {
      s.closest_within(reflect(smp.p[i], pl), cap, match[i], &match[i]);
      dist[i] = match[i].dist_mm;
    }
    std::vector<double> sorted = dist;
    std::nth_element(sorted.begin(), sorted.begin() + N / 2, sorted.end());
    tau = std::min(cap, std::max(2.5 * sorted[N / 2], 0.3));
    Eigen::Vector3d t1 = pl.n.unitOrthogonal(), t2 = pl.n.cross(t1);
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < N; ++i) {
      if (dist[i] > tau) continue;
      // The mirrored normal of the sample must agree with the matched face (rejects matches
      // on the wrong side of thin parts).
      const Eigen::Vector3d rn = smp.n[i] - 2.0 * pl.n.dot(smp.n[i]) * pl.n;
      const Eigen::Vector3d& c = match[i].c;
      const Eigen::Vector3d& m = match[i].n;
      if (rn.dot(m) < 0.3) continue;
      const Eigen::Vector3d& p = smp.p[i];
      const Eigen::Vector3d r = reflect(p, pl);
      const double h = pl.n.dot(p) - pl.d;
      Eigen::Vector3d J(m.dot(-2.0 * t1.dot(p) * pl.n - 2.0 * h * t1), m.dot(-2.0 * t2.dot(p) * pl.n - 2.0 * h * t2),
                        m.dot(2.0 * pl.n));
      const double e = m.dot(r - c);
      A += J * J.transpose();
      b -= J * e;
    }
    A.diagonal().array() += 1e-9 * (A.trace() + 1.0);
    const Eigen::Vector3d x = A.ldlt().solve(b);
    if (!x.allFinite()) break;
    pl.n = (pl.n + x[0] * t1 + x[1] * t2).normalized();
    pl.d += x[2];
    if (std::abs(x[0]) + std::abs(x[1]) < stop.step_rad && std::abs(x[2]) < stop.step_mm && it > 2) break;
  }
  SymmetryResult res;
  res.plane = pl;
  double sq = 0.0;
  std::size_t in = 0;
  for (std::size_t i = 0; i < N; ++i) {
    s.closest_within(reflect(smp.p[i], pl), cap, match[i], &match[i]);
    const double dd = match[i].dist_mm;
    if (dd <= tau) sq += dd * dd, ++in;
  }
  res.inlier_fraction = double(in) / double(N);
  res.rms_mm = in ? std::sqrt(sq / double(in)) : 0.0;
  return res;
}

}  // namespace

SurfaceSamples sample_surface(const SurfaceMesh& mesh, std::size_t count, unsigned seed) {
  std::vector<pipeline::FaceIndex> fs;
  std::vector<double> cum;
  double total = 0.0;
  for (auto f : faces(mesh)) {
    auto h = halfedge(f, mesh);
    const auto a = to_eigen(mesh.point(source(h, mesh))), b = to_eigen(mesh.point(target(h, mesh))),
               c = to_eigen(mesh.point(target(next(h, mesh), mesh)));
    const double area = 0.5 * (b - a).cross(c - a).norm();
    if (!(area > 0.0) || !std::isfinite(area)) continue;
    total += area;
    fs.push_back(f);
    cum.push_back(total);
  }
  if (fs.empty()) throw pipeline::bad_input("surface", "no face of positive area");
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  SurfaceSamples s;
  s.p.reserve(count);
  s.n.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t k = std::lower_bound(cum.begin(), cum.end(), U(rng) * total) - cum.begin();
    auto h = halfedge(fs[std::min(k, fs.size() - 1)], mesh);
    const auto a = to_eigen(mesh.point(source(h, mesh))), b = to_eigen(mesh.point(target(h, mesh))),
               c = to_eigen(mesh.point(target(next(h, mesh), mesh)));
    double u = U(rng), v = U(rng);
    if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
    s.p.push_back(a + u * (b - a) + v * (c - a));
    s.n.push_back((b - a).cross(c - a).normalized());
  }
  return s;
}

void sample_moments(const SurfaceSamples& s, Eigen::Vector3d& mean, Eigen::Matrix3d& cov) {
  mean.setZero();
  for (const auto& p : s.p) mean += p;
  mean /= double(s.p.size());
  cov.setZero();
  for (const auto& p : s.p) cov += (p - mean) * (p - mean).transpose();
  cov /= double(s.p.size());
}

std::vector<double> capped_distances(const SurfaceMesh& mesh, const std::vector<Eigen::Vector3d>& queries,
                                     double cap_mm, bool seed_with_previous) {
  const Surface surf(mesh);
  std::vector<double> d;
  d.reserve(queries.size());
  Match m;
  for (const auto& q : queries) {
    surf.closest_within(q, cap_mm, m, seed_with_previous ? &m : nullptr);
    d.push_back(m.found() ? m.dist_mm : cap_mm);
  }
  return d;
}

SymmetryResult find_symmetry_plane(const SurfaceMesh& mesh, std::size_t samples) {
  const SurfaceSamples smp = sample_surface(mesh, samples);
  Eigen::Vector3d mean;
  Eigen::Matrix3d cov;
  sample_moments(smp, mean, cov);
  const double size = 2.0 * std::sqrt(cov.trace());  // ~ object diameter [mm]
  const double cap = 0.04 * size;
  const Surface surf(mesh);

  // 1. Candidate normals: principal axes + a Fibonacci hemisphere.
  std::vector<Eigen::Vector3d> dirs;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  for (int k = 0; k < 3; ++k) dirs.push_back(eig.eigenvectors().col(k));
  const int M = 150;
  for (int i = 0; i < M; ++i) {
    const double z = (i + 0.5) / M, r = std::sqrt(1.0 - z * z), phi = i * 2.399963229728653;
    dirs.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  // Scored in two passes: all candidates on ~150 samples, then the best 30 again on ~600 (the
  // mean of ~150 capped distances is within ~0.3 mm of the ~600 one, while the planes that can
  // reach the symmetric basin score lowest by far more); a quarter of the queries of one pass.
  std::vector<std::pair<double, Plane>> scored;
  const std::size_t stride = std::max<std::size_t>(1, smp.p.size() / 600);
  for (const auto& n : dirs) {
    Plane pl{n.normalized(), n.normalized().dot(mean)};
    scored.push_back({truncated_score(surf, smp, 4 * stride, pl, cap), pl});
  }
  auto by_score = [](const auto& a, const auto& b) { return a.first < b.first; };
  std::sort(scored.begin(), scored.end(), by_score);
  scored.resize(std::min<std::size_t>(scored.size(), 30));
  for (auto& [sc, pl] : scored) sc = truncated_score(surf, smp, stride, pl, cap);
  std::sort(scored.begin(), scored.end(), by_score);

  // 2. Refine the best distinct candidates (> 12° apart) and keep the most symmetric result.
  std::vector<Plane> picked;
  for (const auto& [sc, pl] : scored) {
    bool distinct = true;
    for (const auto& q : picked) distinct = distinct && std::abs(q.n.dot(pl.n)) < std::cos(12.0 * M_PI / 180.0);
    if (distinct) picked.push_back(pl);
    if (picked.size() == 3) break;
  }
  // Refinement on every rs-th sample: all of them up to 4999 (the default 4000), 2500-4999 above
  // (2500 pin the plane to well under 0.1°); more samples only densify the scoring's strides.
  SurfaceSamples sub;
  const std::size_t rs = std::max<std::size_t>(1, smp.p.size() / 2500);
  for (std::size_t i = 0; i < smp.p.size(); i += rs) sub.p.push_back(smp.p[i]), sub.n.push_back(smp.n[i]);
  // Coarse to fine: the candidates are first refined on ~500 of those samples, which settles
  // which basin each falls into (a wrong candidate oscillates for all 30 iterations, and on the
  // full subset those were most of the search's CPU); only the most symmetric is then refined
  // on the full subset, from near its optimum.
  SurfaceSamples coarse;
  const std::size_t cs = std::max<std::size_t>(1, sub.p.size() / 500);
  for (std::size_t i = 0; i < sub.p.size(); i += cs) coarse.p.push_back(sub.p[i]), coarse.n.push_back(sub.n[i]);
  const IcpStop coarse_stop{30, 1e-4, 1e-2};
  Plane best_plane;
  double best_score = std::numeric_limits<double>::infinity();
  for (const auto& pl : picked) {
    const SymmetryResult r = refine(surf, coarse, pl, cap, coarse_stop);
    const double sc = truncated_score(surf, smp, stride, r.plane, cap);
    if (sc < best_score && r.inlier_fraction > 0.2) best_score = sc, best_plane = r.plane;
  }
  SymmetryResult best;
  if (std::isfinite(best_score)) {
    best = refine(surf, sub, best_plane, cap);
    if (!(best.inlier_fraction > 0.2)) best_score = std::numeric_limits<double>::infinity();
  }
  if (!std::isfinite(best_score))
    throw pipeline::algorithm_failed("surface", "no reflective symmetry plane found (no candidate converged)");
  return best;
}

}  // namespace scan2cad::internal
