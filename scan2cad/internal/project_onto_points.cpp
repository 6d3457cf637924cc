// Projection of a mesh onto oriented points and untangling of the crossings it makes; see
// project_onto_points.h.
#include "scan2cad/internal/project_onto_points.h"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <boost/iterator/counting_iterator.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <iterator>

#include "scan2cad/fill_holes.h"
#include "scan2cad/internal/cleanup.h"

namespace PMP = CGAL::Polygon_mesh_processing;
using pipeline::Point;
using pipeline::SurfaceMesh;
using pipeline::Vector;

namespace scan2cad::internal {

using PN = std::pair<Point, Vector>;

PointTree::PointTree(const std::vector<PN>& pn) : pts_(pn.size()) {
  for (std::size_t i = 0; i < pn.size(); ++i) pts_[i] = pn[i].first;
  ppmap_ = CGAL::make_property_map(pts_);
  tree_ = std::make_unique<Search::Tree>(boost::counting_iterator<std::size_t>(0),
                                         boost::counting_iterator<std::size_t>(pts_.size()), Search::Tree::Splitter(),
                                         Traits(ppmap_));
}

double point_normal_sign(const SurfaceMesh& mesh, const std::vector<PN>& pn, const PointTree& tree) {
  double vote = 0;
  for (auto v : mesh.vertices())
    if (!mesh.is_isolated(v))
      vote += PMP::compute_vertex_normal(v, mesh) * pn[tree.nearest(mesh.point(v), 1).begin()->first].second;
  return vote < 0 ? -1.0 : 1.0;
}

ProjectionStats project_onto_points(SurfaceMesh& mesh, const std::vector<pipeline::VertexIndex>& vertices, double sign,
                                    const std::vector<PN>& pn, const PointTree& tree, unsigned k, double spacing_mm,
                                    double max_move_mm) {
  ProjectionStats ps;
  ps.vertices = vertices.size();
  if (pn.size() < k || mesh.is_empty()) return ps;
  std::vector<Point> moved(vertices.size());
  double sum_move = 0;
  std::vector<Eigen::Vector3d> local;
  for (std::size_t iv = 0; iv < vertices.size(); ++iv) {
    const auto v = vertices[iv];
    const Point p = mesh.point(v);
    moved[iv] = p;
    if (mesh.is_isolated(v)) continue;
    const Vector nv = PMP::compute_vertex_normal(v, mesh);
    if (nv == Vector(0, 0, 0)) continue;
    const Eigen::Vector3d w(nv.x(), nv.y(), nv.z());
    const Eigen::Vector3d u = w.unitOrthogonal(), t = w.cross(u);
    local.clear();
    double nearest2 = 1e300, farthest2 = 0;
    for (const auto& nb : tree.nearest(p, k)) {
      if (sign * (pn[nb.first].second * nv) < 0.5) continue;  // other side of a thin feature
      const Point& q = tree.point(nb.first);
      const Eigen::Vector3d d(q.x() - p.x(), q.y() - p.y(), q.z() - p.z());
      local.emplace_back(d.dot(u), d.dot(t), d.dot(w));
      nearest2 = std::min(nearest2, nb.second);
      farthest2 = std::max(farthest2, nb.second);
    }
    if (local.size() < 6 || nearest2 > 4.0 * spacing_mm * spacing_mm) {
      ++ps.unsupported;
      continue;
    }
    // height h(x, y) = c0 + c1 x + c2 y + c3 x^2 + c4 x y + c5 y^2; the vertex goes to c0
    const double sigma2 = std::max(farthest2, 1e-12) / 4.0;
    const bool quadric = local.size() >= 10;
    const int n_coef = quadric ? 6 : 3;
    Eigen::MatrixXd a(local.size(), n_coef);
    Eigen::VectorXd b(local.size());
    for (std::size_t i = 0; i < local.size(); ++i) {
      const double x = local[i].x(), y = local[i].y();
      const double wi = std::exp(-(x * x + y * y) / (2.0 * sigma2));
      a(long(i), 0) = wi, a(long(i), 1) = wi * x, a(long(i), 2) = wi * y;
      if (quadric) a(long(i), 3) = wi * x * x, a(long(i), 4) = wi * x * y, a(long(i), 5) = wi * y * y;
      b(long(i)) = wi * local[i].z();
    }
    const double c0 = a.colPivHouseholderQr().solve(b)(0);
    if (!std::isfinite(c0) || std::abs(c0) > max_move_mm) {
      ++ps.unsupported;
      continue;
    }
    moved[iv] = p + c0 * Vector(w.x(), w.y(), w.z());
    ++ps.moved;
    sum_move += std::abs(c0);
    ps.max_move_mm = std::max(ps.max_move_mm, std::abs(c0));
  }
  for (std::size_t iv = 0; iv < vertices.size(); ++iv) mesh.point(vertices[iv]) = moved[iv];
  ps.mean_move_mm = ps.moved ? sum_move / double(ps.moved) : 0;
  return ps;
}

UntangleStats untangle_crossings(SurfaceMesh& mesh, double sign, const std::vector<PN>& pn, const PointTree& tree,
                                 unsigned k, double spacing_mm, double max_move_mm, int max_rounds) {
  UntangleStats us;
  auto was_border = mesh.add_property_map<pipeline::VertexIndex, char>("v:untangle_was_border", 0).first;
  for (;; ++us.rounds) {
    if (us.rounds == max_rounds) {
      us.crossing_left = count_self_intersecting_faces(mesh);
      break;
    }
    for (auto v : mesh.vertices()) was_border[v] = mesh.is_border(v);
    const SelfIntersectionsCut cut = remove_self_intersecting_faces(mesh);
    if (cut.faces_cut == 0) break;
    us.faces_cut += cut.faces_cut;
    us.piece_faces_removed += cut.pieces.faces_removed;
    std::vector<SurfaceMesh::Halfedge_index> loops;
    PMP::extract_boundary_cycles(mesh, std::back_inserter(loops));
    std::vector<pipeline::VertexIndex> fresh;
    for (auto h : loops) {
      bool scan_hole = false;
      for (auto e : CGAL::halfedges_around_face(h, mesh)) scan_hole |= was_border[mesh.target(e)] != 0;
      if (scan_hole) continue;
      std::vector<pipeline::VertexIndex> verts;
      if (fill_hole(mesh, h, spacing_mm, nullptr, &verts).filled) ++us.gaps_filled;
      fresh.insert(fresh.end(), verts.begin(), verts.end());
    }
    us.vertices_projected += project_onto_points(mesh, fresh, sign, pn, tree, k, spacing_mm, max_move_mm).moved;
  }
  mesh.remove_property_map(was_border);
  return us;
}

}  // namespace scan2cad::internal
