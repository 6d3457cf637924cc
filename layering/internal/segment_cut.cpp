#include "layering/internal/segment_cut.h"

#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>

namespace layering::internal {

using pipeline::SurfaceMesh;
using Halfedge = SurfaceMesh::Halfedge_index;

void cut_at_zero(SurfaceMesh& mesh, std::vector<Field>& fields, std::size_t cut, double snap) {
  Field& f = fields[cut];
  for (auto v : mesh.vertices())
    if (std::abs(f[v]) < snap) f[v] = 0.0;

  // 1. Split every strictly crossing edge at the interpolated zero.
  std::vector<Halfedge> crossing;
  for (auto e : mesh.edges()) {
    const Halfedge h = mesh.halfedge(e);
    const double a = f[mesh.source(h)], b = f[mesh.target(h)];
    if ((a < 0 && b > 0) || (a > 0 && b < 0)) crossing.push_back(h);
  }
  for (Halfedge h : crossing) {
    const auto va = mesh.source(h), vb = mesh.target(h);
    const double t = f[va] / (f[va] - f[vb]);
    const pipeline::Point pa = mesh.point(va), pb = mesh.point(vb);
    std::vector<double> values(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) values[i] = (1 - t) * fields[i][va] + t * fields[i][vb];
    const Halfedge hnew = CGAL::Euler::split_edge(h, mesh);  // target(hnew) is the new vertex
    const auto vn = mesh.target(hnew);
    mesh.point(vn) = pipeline::Point(pa.x() + t * (pb.x() - pa.x()), pa.y() + t * (pb.y() - pa.y()),
                                     pa.z() + t * (pb.z() - pa.z()));
    for (std::size_t i = 0; i < fields.size(); ++i) fields[i][vn] = values[i];
    f[vn] = 0.0;
  }

  // 2. In every face with two non-adjacent zero vertices, add the edge joining them: this
  //    separates the negative and the positive corners.
  std::vector<SurfaceMesh::Face_index> faces(mesh.faces().begin(), mesh.faces().end());
  for (auto fc : faces) {
    std::vector<Halfedge> zeros;
    bool neg = false, pos = false;
    for (Halfedge h : CGAL::halfedges_around_face(mesh.halfedge(fc), mesh)) {
      const double v = f[mesh.target(h)];
      if (v == 0.0) zeros.push_back(h);
      neg |= v < 0;
      pos |= v > 0;
    }
    if (!(neg && pos) || zeros.size() != 2) continue;
    const Halfedge h1 = zeros[0], h2 = zeros[1];
    if (mesh.next(h1) == h2 || mesh.next(h2) == h1) continue;  // adjacent: nothing to separate
    CGAL::Euler::split_face(h1, h2, mesh);
  }

  // 3. The pieces left with four corners are triangulated.
  CGAL::Polygon_mesh_processing::triangulate_faces(mesh);
}

}  // namespace layering::internal
