// Point cloud → triangle mesh with CGAL (outliers, normals, Poisson / advancing front / scale space).
//
// Choice of the default for heads: Poisson. Measured (bench_scan2cad, NIOSH medium, 200k points,
// 0.3 mm noise, 1 % outliers, three 10–20 mm holes): after repair, p95 distance 0.21 mm, mean
// 0.08 mm, closed and manifold; it approximates rather than interpolates, so its error sits
// below the noise, and it closes scan holes by itself. Respirator shells are open: Poisson would
// close the rim, so they default to advancing front, which keeps open borders. Advancing front
// and scale space were not yet measured on the heads (see README.md).
#include "scan2cad/reconstruct.h"

#include <CGAL/Advancing_front_surface_reconstruction.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Scale_space_reconstruction_3/Advancing_front_mesher.h>
#include <CGAL/Scale_space_reconstruction_3/Weighted_PCA_smoother.h>
#include <CGAL/Scale_space_surface_reconstruction_3.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/grid_simplify_point_set.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/jet_smooth_point_set.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/poisson_surface_reconstruction.h>
#include <CGAL/remove_outliers.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <utility>

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"
#include "pipeline/progress.h"

namespace PMP = CGAL::Polygon_mesh_processing;
using pipeline::Point;
using pipeline::SurfaceMesh;
using pipeline::Vector;

namespace scan2cad {

namespace {

using PN = std::pair<Point, Vector>;
using PointMap = CGAL::First_of_pair_property_map<PN>;
using NormalMap = CGAL::Second_of_pair_property_map<PN>;
constexpr std::size_t min_points = 100;

// Builds an oriented Surface_mesh from the triangles of an interpolating reconstruction.
SurfaceMesh mesh_from_triangles(const std::vector<Point>& pts, const std::vector<std::array<std::size_t, 3>>& tris) {
  std::vector<Point> points = pts;
  std::vector<std::vector<std::size_t>> polys(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) polys[i].assign(tris[i].begin(), tris[i].end());
  PMP::orient_polygon_soup(points, polys);
  SurfaceMesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polys, mesh);
  mesh.collect_garbage();
  return mesh;
}

// Turns the mesh so its face normals agree with the (outward) point normals: an interpolating
// mesh has an arbitrary orientation per connected component; one global vote is enough here
// because heads and respirator shells are one component after repair keeps the largest.
// pts[i] is the (possibly smoothed) position of pn[i].
void orient_like_normals(SurfaceMesh& mesh, const std::vector<Point>& pts, const std::vector<PN>& pn) {
  if (pn.empty() || mesh.is_empty()) return;
  std::map<Point, Vector> normal_of;
  for (std::size_t i = 0; i < pts.size(); ++i) normal_of.emplace(pts[i], pn[i].second);
  double vote = 0;
  for (auto v : mesh.vertices()) {
    if (mesh.is_isolated(v)) continue;
    const auto it = normal_of.find(mesh.point(v));
    if (it != normal_of.end()) vote += PMP::compute_vertex_normal(v, mesh) * it->second;
  }
  if (vote < 0) PMP::reverse_face_orientations(mesh);
}

}  // namespace

ScanKind parse_scan_kind(const std::string& name) {
  if (name == "head") return ScanKind::head;
  if (name == "respirator") return ScanKind::respirator;
  throw pipeline::Error(pipeline::ErrorKind::usage, "--kind: '" + name + "', expected head or respirator");
}
std::string scan_kind_name(ScanKind k) { return k == ScanKind::head ? "head" : "respirator"; }
double expected_size_mm(ScanKind k) { return k == ScanKind::head ? 250.0 : 130.0; }

ReconstructMethod parse_reconstruct_method(const std::string& name, ScanKind kind) {
  if (name == "auto") return kind == ScanKind::head ? ReconstructMethod::poisson : ReconstructMethod::advancing_front;
  if (name == "poisson") return ReconstructMethod::poisson;
  if (name == "advancing_front") return ReconstructMethod::advancing_front;
  if (name == "scale_space") return ReconstructMethod::scale_space;
  throw pipeline::Error(pipeline::ErrorKind::usage,
                        "--method: '" + name + "', expected auto, poisson, advancing_front or scale_space");
}
std::string reconstruct_method_name(ReconstructMethod m) {
  switch (m) {
    case ReconstructMethod::poisson: return "poisson";
    case ReconstructMethod::advancing_front: return "advancing_front";
    default: return "scale_space";
  }
}

SurfaceMesh reconstruct(const pipeline::PointCloud& cloud, ScanKind kind, const ReconstructOptions& opt,
                        ReconstructStats* stats_out) {
  ReconstructStats st;
  st.input_points = cloud.points.size();
  if (cloud.points.size() < min_points)
    throw pipeline::bad_input("point cloud", std::to_string(cloud.points.size()) +
                                                 " points are too few to define a surface, expected at least " +
                                                 std::to_string(min_points));
  const bool has_normals = cloud.normals.size() == cloud.points.size();
  std::vector<PN> pn(cloud.points.size());
  for (std::size_t i = 0; i < pn.size(); ++i) pn[i] = {cloud.points[i], has_normals ? cloud.normals[i] : Vector(0, 0, 0)};
  const unsigned k = unsigned(opt.neighbors);
  pipeline::Progress progress("reconstruct", 0);

  // 1. Thin dense scans to a grid (bounds time and memory; the output is remeshed anyway).
  if (opt.simplify_cell_mm > 0) {
    progress.step("grid simplification");
    pn.erase(CGAL::grid_simplify_point_set(pn, opt.simplify_cell_mm, CGAL::parameters::point_map(PointMap())), pn.end());
  }

  // 2. Outliers: mean k-NN distance above outlier_factor × the cloud's average spacing.
  progress.step("outlier removal");
  const double spacing0 = CGAL::compute_average_spacing<CGAL::Sequential_tag>(pn, k, CGAL::parameters::point_map(PointMap()));
  const std::size_t before = pn.size();
  pn.erase(CGAL::remove_outliers<CGAL::Sequential_tag>(pn, k, CGAL::parameters::point_map(PointMap())
                                                                  .threshold_percent(100.0)
                                                                  .threshold_distance(opt.outlier_factor * spacing0)),
           pn.end());
  st.outliers_removed = before - pn.size();
  if (pn.size() < min_points)
    throw pipeline::bad_input("point cloud", "only " + std::to_string(pn.size()) +
                                                 " points left after outlier removal, expected at least " +
                                                 std::to_string(min_points));

  // 3. Denoise and remove spikes: each point is projected onto the jet (quadric) fitted to its
  //    k neighbours (CGAL). A spike (a point several mm off the surface) stays near its
  //    neighbours in k-NN distance, so step 2 misses it, but its projection moves it by its
  //    height: points moved by more than 4 robust standard deviations (1.4826 × median move)
  //    are removed, the others keep their denoised position.
  progress.step("jet smoothing and spike removal");
  {
    std::vector<PN> smoothed = pn;
    CGAL::jet_smooth_point_set<CGAL::Sequential_tag>(smoothed, k, CGAL::parameters::point_map(PointMap()));
    std::vector<double> move(pn.size());
    for (std::size_t i = 0; i < pn.size(); ++i) move[i] = std::sqrt(CGAL::squared_distance(pn[i].first, smoothed[i].first));
    std::vector<double> sorted = move;
    std::nth_element(sorted.begin(), sorted.begin() + long(sorted.size() / 2), sorted.end());
    const double limit = 4.0 * 1.4826 * sorted[sorted.size() / 2];
    std::vector<PN> kept;
    kept.reserve(pn.size());
    for (std::size_t i = 0; i < pn.size(); ++i)
      if (move[i] <= limit) kept.push_back({smoothed[i].first, pn[i].second});
    st.outliers_removed += pn.size() - kept.size();
    pn.swap(kept);
  }

  // 4. Normals: jet fitting + minimum-spanning-tree orientation (CGAL), when the scan has none.
  if (!has_normals) {
    progress.step("normal estimation and orientation");
    CGAL::jet_estimate_normals<CGAL::Sequential_tag>(pn, k, CGAL::parameters::point_map(PointMap()).normal_map(NormalMap()));
    // points MST cannot reach are dropped: their normal would be a coin toss
    pn.erase(CGAL::mst_orient_normals(pn, k, CGAL::parameters::point_map(PointMap()).normal_map(NormalMap())), pn.end());
    st.normals_estimated = true;
  }
  // spacing = mean distance to the 6 nearest neighbours (CGAL's Poisson convention)
  st.spacing_mm = CGAL::compute_average_spacing<CGAL::Sequential_tag>(pn, 6, CGAL::parameters::point_map(PointMap()));
  st.points_used = pn.size();

  // 5. Reconstruction.
  SurfaceMesh mesh;
  progress.step(reconstruct_method_name(opt.method) + " reconstruction of " + std::to_string(pn.size()) + " points");
  if (opt.method == ReconstructMethod::poisson) {
    // Contouring: facets within opt.poisson_distance_mm of the implicit surface (CGAL's default
    // 0.375 × spacing would be 0.3–0.6 mm here, above the accuracy asked for) and of radius
    // ≤ 30 × spacing; repair remeshes the result anyway.
    if (!CGAL::poisson_surface_reconstruction_delaunay(pn.begin(), pn.end(), PointMap(), NormalMap(), mesh,
                                                       st.spacing_mm, 20.0, 30.0,
                                                       // CGAL's surface mesher fails ("already inserted")
                                                       // below ~0.1 × spacing on sparse clouds
                                                       std::max(opt.poisson_distance_mm / st.spacing_mm, 0.1)))
      throw pipeline::algorithm_failed("point cloud", "Poisson reconstruction failed (normals inconsistent?)");
    if (CGAL::is_closed(mesh) && !PMP::is_outward_oriented(mesh)) PMP::reverse_face_orientations(mesh);
  } else {
    std::vector<Point> pts(pn.size());
    std::vector<std::array<std::size_t, 3>> tris;
    if (opt.method == ReconstructMethod::advancing_front) {
      for (std::size_t i = 0; i < pn.size(); ++i) pts[i] = pn[i].first;
      CGAL::advancing_front_surface_reconstruction(pts.begin(), pts.end(), std::back_inserter(tris), 5.0, 0.52);
    } else {
      CGAL::Scale_space_surface_reconstruction_3<pipeline::Kernel> ss;
      for (const auto& p : pn) ss.insert(p.first);
      ss.increase_scale(4, CGAL::Scale_space_reconstruction_3::Weighted_PCA_smoother<pipeline::Kernel>(k));
      ss.reconstruct_surface(CGAL::Scale_space_reconstruction_3::Advancing_front_mesher<pipeline::Kernel>(10 * st.spacing_mm));
      std::size_t i = 0;
      for (auto it = ss.points_begin(); it != ss.points_end(); ++it) pts[i++] = *it;
      for (auto it = ss.facets_begin(); it != ss.facets_end(); ++it) tris.push_back({(*it)[0], (*it)[1], (*it)[2]});
    }
    if (tris.empty()) throw pipeline::algorithm_failed("point cloud", "reconstruction produced no triangles");
    mesh = mesh_from_triangles(pts, tris);
    orient_like_normals(mesh, pts, pn);
  }
  (void)kind;
  if (mesh.number_of_faces() == 0) throw pipeline::algorithm_failed("point cloud", "reconstruction produced no triangles");
  st.vertices = mesh.number_of_vertices();
  st.faces = mesh.number_of_faces();
  progress.finish(std::to_string(st.faces) + " triangles from " + std::to_string(st.points_used) + " points");
  if (stats_out) *stats_out = st;
  return mesh;
}

void write_soup_ply(const std::string& path, const pipeline::PolygonSoup& soup) {
  pipeline::write_atomic(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    CGAL::IO::set_binary_mode(out);
    if (!CGAL::IO::write_PLY(out, soup.points, soup.polygons) || !out.flush())
      throw pipeline::io_failed(path, "cannot write PLY");
  });
}

}  // namespace scan2cad
