// Symmetric hole completion; the method is in complete_by_symmetry.h.
#include "scan2cad/complete_by_symmetry.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>

#include "pipeline/error.h"
#include "scan2cad/internal/align_symmetry.h"

namespace PMP = CGAL::Polygon_mesh_processing;
using pipeline::FaceIndex;
using pipeline::SurfaceMesh;
using pipeline::VertexIndex;

namespace scan2cad {

namespace {

using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel, Primitive>>;

Eigen::Vector3d to_eigen(const pipeline::Point& p) { return {p.x(), p.y(), p.z()}; }
Eigen::Vector3d to_eigen(const pipeline::Vector& v) { return {v.x(), v.y(), v.z()}; }

constexpr std::size_t none = std::size_t(-1);
// Per-element arrays are sized by num_vertices() / num_faces(), which count removed elements too,
// so every index of a mesh with garbage fits.

/// Harmonic interpolation over the vertex set `domain` (uniform graph Laplacian): a vertex with
/// known[i] keeps values[i]; every other one becomes the mean of its neighbours in `domain`.
/// Neighbours outside `domain` are left out (a free edge). A connected part of the domain without
/// a known vertex keeps zeros. The blended fields (a hole's asymmetry, the moves of unmatched
/// vertices) are smooth and small, on the near-uniform triangles of a refined fill: the uniform
/// weights are enough there, and unlike cotangent weights they are positive on any triangle.
/// Returns false (values unchanged) if the sparse solve fails.
bool harmonic_fill(const SurfaceMesh& mesh, const std::vector<VertexIndex>& domain, const std::vector<char>& known,
                   std::vector<Eigen::Vector3d>& values) {
  std::vector<std::size_t> slot(mesh.num_vertices(), none);
  for (std::size_t i = 0; i < domain.size(); ++i) slot[std::size_t(domain[i])] = i;
  std::vector<std::size_t> unknown_of(domain.size(), none);
  std::size_t n = 0;
  for (std::size_t i = 0; i < domain.size(); ++i)
    if (!known[i]) unknown_of[i] = n++;
  if (n == 0) return true;
  std::vector<Eigen::Triplet<double>> a;
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(static_cast<long>(n), 3);
  for (std::size_t i = 0; i < domain.size(); ++i) {
    if (known[i]) continue;
    const long row = long(unknown_of[i]);
    double degree = 0;
    for (VertexIndex w : CGAL::vertices_around_target(mesh.halfedge(domain[i]), mesh)) {
      const std::size_t j = slot[std::size_t(w)];
      if (j == none) continue;
      degree += 1;
      if (known[j])
        b.row(row) += values[j].transpose();
      else
        a.emplace_back(row, long(unknown_of[j]), -1.0);
    }
    // a vertex with no neighbour in the domain keeps 0 (degree 1 with zero right-hand side)
    a.emplace_back(row, row, std::max(degree, 1.0));
  }
  const long size = long(n);
  Eigen::SparseMatrix<double> m(size, size);
  m.setFromTriplets(a.begin(), a.end());
  // A part of the domain without a known vertex would make the system singular: a tiny
  // diagonal term keeps it definite and that part at ~0 (its right-hand side is 0).
  for (long i = 0; i < size; ++i) m.coeffRef(i, i) += 1e-9;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(m);
  if (solver.info() != Eigen::Success) return false;
  const Eigen::MatrixXd x = solver.solve(b);
  if (solver.info() != Eigen::Success || !x.allFinite()) return false;
  for (std::size_t i = 0; i < domain.size(); ++i)
    if (!known[i]) values[i] = x.row(long(unknown_of[i])).transpose();
  return true;
}

}  // namespace

SymmetricCompletionReport complete_fills_by_symmetry(SurfaceMesh& mesh, const std::vector<std::vector<FaceIndex>>& fills,
                                                     const SymmetricCompletionOptions& opt) {
  SymmetricCompletionReport rep;
  rep.holes.resize(fills.size());
  if (fills.empty()) {
    rep.skipped = "no filled hole";
    return rep;
  }
  internal::SymmetryResult sym;
  try {
    sym = internal::find_symmetry_plane(mesh);
  } catch (const pipeline::Error& e) {
    rep.skipped = std::string("no symmetry plane: ") + e.what();
    return rep;
  }
  rep.plane_found = true;
  rep.plane_normal = sym.plane.n;
  rep.plane_offset_mm = sym.plane.d;
  rep.plane_rms_mm = sym.rms_mm;
  rep.plane_inliers = sym.inlier_fraction;
  if (sym.rms_mm > opt.max_plane_rms_mm || sym.inlier_fraction < opt.min_plane_inliers) {
    rep.skipped = "the surface is not symmetric enough";
    return rep;
  }
  const Eigen::Vector3d pn = sym.plane.n;
  const double pd = sym.plane.d;
  auto reflect = [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(p - 2.0 * (pn.dot(p) - pd) * pn); };
  auto reflect_dir = [&](const Eigen::Vector3d& v) { return Eigen::Vector3d(v - 2.0 * pn.dot(v) * pn); };

  std::vector<char> fill_face(mesh.num_faces(), 0);
  for (const auto& f : fills)
    for (FaceIndex fi : f) fill_face[std::size_t(fi)] = 1;
  Tree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.accelerate_distance_queries();

  // d = mirror(match) − p for one vertex, false when its mirror image has no scanned match
  auto mirror_move = [&](VertexIndex v, Eigen::Vector3d& d) {
    const Eigen::Vector3d p = to_eigen(mesh.point(v));
    const Eigen::Vector3d m = reflect(p);
    const auto hit = tree.closest_point_and_primitive(pipeline::Point(m.x(), m.y(), m.z()));
    if (fill_face[std::size_t(hit.second)]) return false;
    const Eigen::Vector3d c = to_eigen(hit.first);
    if ((c - m).norm() > opt.max_mirror_distance_mm) return false;
    const Eigen::Vector3d face_n = to_eigen(PMP::compute_face_normal(hit.second, mesh));
    const Eigen::Vector3d vertex_n = to_eigen(PMP::compute_vertex_normal(v, mesh));
    if (reflect_dir(vertex_n).dot(face_n) < 0.5) return false;
    d = reflect(c) - p;
    return true;
  };

  // Each fill's own vertices (all their faces are that fill's), marked for all fills first, so
  // that one hole's rings never walk into another hole's fill.
  std::vector<char> in_fill(mesh.num_vertices(), 0), this_fill(mesh.num_faces(), 0);
  std::vector<std::vector<VertexIndex>> fill_vertices(fills.size());
  for (std::size_t h = 0; h < fills.size(); ++h) {
    for (FaceIndex f : fills[h]) this_fill[std::size_t(f)] = 1;
    for (FaceIndex f : fills[h])
      for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
        if (in_fill[std::size_t(v)]) continue;
        bool only_fill = true;
        for (FaceIndex g : CGAL::faces_around_target(mesh.halfedge(v), mesh))
          only_fill = only_fill && g != SurfaceMesh::null_face() && this_fill[std::size_t(g)];
        if (only_fill) in_fill[std::size_t(v)] = 1, fill_vertices[h].push_back(v);
      }
    for (FaceIndex f : fills[h]) this_fill[std::size_t(f)] = 0;
  }

  // All targets come from the mesh as filled; the moves are applied at the end.
  std::vector<std::pair<VertexIndex, Eigen::Vector3d>> moves;
  std::vector<char> moved(mesh.num_vertices(), 0);
  for (std::size_t h = 0; h < fills.size(); ++h) {
    SymmetricHoleCompletion& hr = rep.holes[h];
    const std::vector<VertexIndex>& fill_v = fill_vertices[h];
    // the scanned vertices by rings outward from the fill's border (depth 0)
    std::vector<VertexIndex> rings;
    std::vector<int> depth(mesh.num_vertices(), -1);
    for (FaceIndex f : fills[h])
      for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
        if (!in_fill[std::size_t(v)] && depth[std::size_t(v)] == -1) depth[std::size_t(v)] = 0, rings.push_back(v);
    const int last_depth = opt.border_band_rings + opt.ring_width - 1;
    for (std::size_t i = 0; i < rings.size(); ++i) {  // breadth first
      const VertexIndex v = rings[i];
      if (depth[std::size_t(v)] >= last_depth) continue;
      for (VertexIndex w : CGAL::vertices_around_target(mesh.halfedge(v), mesh))
        if (depth[std::size_t(w)] == -1 && !in_fill[std::size_t(w)]) {
          depth[std::size_t(w)] = depth[std::size_t(v)] + 1;
          rings.push_back(w);
        }
    }
    hr.fill_vertices = fill_v.size();
    if (fill_v.empty() || rings.empty()) continue;

    // domain: the reference rings (depth >= border_band_rings), then the band, then the fill
    std::vector<VertexIndex> domain;
    for (VertexIndex v : rings)
      if (depth[std::size_t(v)] >= opt.border_band_rings) domain.push_back(v);
    const std::size_t n_reference = domain.size();
    for (VertexIndex v : rings)
      if (depth[std::size_t(v)] < opt.border_band_rings) domain.push_back(v);
    hr.band_vertices = domain.size() - n_reference;
    domain.insert(domain.end(), fill_v.begin(), fill_v.end());
    std::vector<Eigen::Vector3d> d(domain.size(), Eigen::Vector3d::Zero());
    std::vector<char> matched(domain.size(), 0);
    double sum2 = 0;
    for (std::size_t i = 0; i < domain.size(); ++i) {
      matched[i] = mirror_move(domain[i], d[i]);
      if (!matched[i]) continue;
      if (i < n_reference) {
        ++hr.ring_matched;
        sum2 += d[i].squaredNorm();
      } else if (i >= n_reference + hr.band_vertices) {
        ++hr.mirrored_vertices;
      }
    }
    hr.ring_vertices = n_reference;
    hr.ring_asymmetry_rms_mm = hr.ring_matched ? std::sqrt(sum2 / double(hr.ring_matched)) : 0;
    if (2 * hr.ring_matched < hr.ring_vertices || hr.ring_asymmetry_rms_mm > opt.max_ring_asymmetry_mm ||
        hr.mirrored_vertices == 0)
      continue;

    // the local asymmetry a: the matched reference rings' d, harmonic over the rest
    std::vector<Eigen::Vector3d> a(domain.size(), Eigen::Vector3d::Zero());
    std::vector<char> known(domain.size(), 0);
    for (std::size_t i = 0; i < n_reference; ++i)
      if (matched[i]) known[i] = 1, a[i] = d[i];
    if (!harmonic_fill(mesh, domain, known, a)) continue;
    // the moves: zero on the reference rings, d − a on the matched band and fill vertices,
    // harmonic in between
    std::vector<Eigen::Vector3d> move(domain.size(), Eigen::Vector3d::Zero());
    std::vector<char> fixed(domain.size(), 0);
    for (std::size_t i = 0; i < domain.size(); ++i)
      if (i < n_reference)
        fixed[i] = 1;
      else if (matched[i])
        fixed[i] = 1, move[i] = d[i] - a[i];
    if (!harmonic_fill(mesh, domain, fixed, move)) continue;
    double sum = 0;
    std::size_t applied = 0;
    for (std::size_t i = n_reference; i < domain.size(); ++i) {
      if (moved[std::size_t(domain[i])]) continue;  // in the band of an earlier hole too
      moved[std::size_t(domain[i])] = 1;
      moves.emplace_back(domain[i], move[i]);
      sum += move[i].norm();
      ++applied;
      hr.max_move_mm = std::max(hr.max_move_mm, move[i].norm());
    }
    hr.mean_move_mm = applied ? sum / double(applied) : 0.0;
    hr.completed = true;
  }
  for (const auto& [v, mv] : moves) mesh.point(v) = mesh.point(v) + pipeline::Vector(mv.x(), mv.y(), mv.z());
  return rep;
}

nlohmann::json SymmetricCompletionReport::to_json() const {
  nlohmann::json holes_j = nlohmann::json::array();
  for (const auto& h : holes)
    holes_j.push_back({{"fill_vertices", h.fill_vertices},
                       {"mirrored_vertices", h.mirrored_vertices},
                       {"band_vertices", h.band_vertices},
                       {"ring_vertices", h.ring_vertices},
                       {"ring_matched", h.ring_matched},
                       {"ring_asymmetry_rms_mm", h.ring_asymmetry_rms_mm},
                       {"completed", h.completed},
                       {"max_move_mm", h.max_move_mm},
                       {"mean_move_mm", h.mean_move_mm}});
  return {{"plane_found", plane_found},
          {"plane_normal", {plane_normal.x(), plane_normal.y(), plane_normal.z()}},
          {"plane_offset_mm", plane_offset_mm},
          {"plane_rms_mm", plane_rms_mm},
          {"plane_inliers", plane_inliers},
          {"skipped", skipped},
          {"holes", holes_j}};
}

}  // namespace scan2cad
