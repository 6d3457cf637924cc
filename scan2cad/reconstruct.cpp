// Point cloud → triangle mesh with CGAL (outliers, normals, Poisson / advancing front / scale space).
//
// Choice of the default for heads: Poisson. Measured (bench_scan2cad, NIOSH medium, 200k points,
// 0.3 mm noise, 1 % outliers, three 10–20 mm holes): after repair, p95 distance 0.21 mm, mean
// 0.08 mm, closed and manifold; it approximates rather than interpolates, so its error sits
// below the noise, and it closes scan holes by itself. Respirator scans of a whole cup are thin
// closed shells: the two sides are separated first and only the inner one (toward the face) is
// kept (orient_thin_shell); advancing front meshes that open sheet and keeps its rim. On the raw
// cup it gave a torn, self-intersecting surface; Poisson on both separated sides gave genus 143.
// All three methods on the heads: README.md, "The three methods on the seven acceptance scans".
#include "scan2cad/reconstruct.h"

#include <CGAL/Advancing_front_surface_reconstruction.h>
#include <CGAL/Cartesian_converter.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/property_map.h>
#include <boost/iterator/transform_iterator.hpp>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Scale_space_reconstruction_3/Advancing_front_mesher.h>
#include <CGAL/Scale_space_reconstruction_3/Weighted_PCA_smoother.h>
#include <CGAL/Scale_space_surface_reconstruction_3.h>
#include <CGAL/grid_simplify_point_set.h>
#include <CGAL/poisson_surface_reconstruction.h>
#include <CGAL/Eigen_solver_traits.h>
#include <Eigen/Eigenvalues>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <utility>

#include "pipeline/error.h"
#include "pipeline/principal_spreads.h"
#include "pipeline/progress.h"
#include "pipeline/units.h"
#include "scan2cad/remove_support_plane.h"
#include "scan2cad/internal/orient_normals.h"
#include "scan2cad/internal/refit_on_own_side.h"
#include "scan2cad/internal/point_set_steps.h"
#include "scan2cad/internal/project_onto_points.h"

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
// Scanner normals follow the surface at nearly every point (see the test); constant ones at ~30 %
// of a head. Below this share a scan's normals are replaced by estimated ones.
constexpr double min_share_of_normals_along_surface = 0.8;

// A scanner's normals, each oriented on its own (a line, not a direction), are as often in as
// out: Poisson took 9.5 minutes on 300,000 such points of a head and made 2,134 triangles 435 mm
// across, which repair then refused as too large (sweep O's scan, half its normals flipped).
// Oriented ones point away from the centre of a head or a cup on nearly all points (a face-only
// scan's too: its centre lies behind the face); an oriented cloud turned inside out toward it.
// Between the two (here 0.2-0.8), they are oriented afresh, as missing ones.
constexpr double max_share_of_unoriented_normals_away = 0.8;

// The share of the points whose normal points away from the points' centroid.
double share_of_normals_away_from_centre(const std::vector<PN>& pn) {
  double c[3] = {0, 0, 0};
  for (const auto& p : pn)
    for (int d = 0; d < 3; ++d) c[d] += p.first[d] / double(pn.size());
  std::size_t away = 0;
  for (const auto& p : pn)
    away += (p.first.x() - c[0]) * p.second.x() + (p.first.y() - c[1]) * p.second.y() + (p.first.z() - c[2]) * p.second.z() > 0;
  return pn.empty() ? 0.0 : double(away) / double(pn.size());
}
// Points that fill a volume (noise, a voxel grid's centres) instead of lying on a surface: their
// 128 nearest points fit no plane. Share of 2,000 points whose neighbours fit a plane with CGAL's
// quality 1 − λmin/λmid ≥ 0.5, measured after the outlier removal: generated small head, one-size
// and three-size S cups 1.000, NIOSH medium and large with 2 mm of noise 0.92 and 0.94; uniform
// points in a head-sized box (2k to 200k) 0.09–0.19, in a 20 mm slab 0.23. With 64 neighbours the
// NIOSH heads with 2 mm of noise fell to 0.45 (0.99 with 0.3 mm).
constexpr unsigned surface_check_neighbors = 128;
constexpr double surface_check_min_quality = 0.5, min_share_of_points_on_a_surface = 0.5;
// The largest share of the points the normal orientation may leave unreached (see its use).
constexpr double max_unreached_share = 0.1;

// The per-point k-NN steps (spacing, outliers, jet smoothing, jet normals) run on all cores
// through internal/point_set_steps.h: CGAL's per-point code with a fixed OpenMP schedule, so the
// output does not depend on the threads' timing.

// Wall and CPU time of each step, on stderr and in ReconstructStats::step_times (issue 2 asks
// where the time goes; std::clock() is the CPU time of the whole process, all threads).
class StepClock {
 public:
  StepClock(pipeline::Progress& progress, ReconstructStats& st) : progress_(progress), st_(st) {}
  void start(const std::string& step) {
    stop();
    progress_.step(step);
    step_ = step;
    wall0_ = std::chrono::steady_clock::now();
    cpu0_ = std::clock();
    running_ = true;
  }
  void stop() {
    if (!running_) return;
    running_ = false;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count();
    const double cpu = double(std::clock() - cpu0_) / CLOCKS_PER_SEC;
    st_.step_times.push_back({step_, wall, cpu});
    char line[64];
    std::snprintf(line, sizeof line, ": %.1f s wall, %.1f s CPU", wall, cpu);
    pipeline::log("reconstruct", "  " + step_ + line);
  }

 private:
  pipeline::Progress& progress_;
  ReconstructStats& st_;
  std::string step_;
  std::chrono::steady_clock::time_point wall0_;
  std::clock_t cpu0_ = 0;
  bool running_ = false;
};

// A vertex or cell base of the contouring's triangulation with a CGAL time stamp. The surface
// mesher keeps std::sets of vertex handles (Surface_mesher_manifold's bad vertices,
// Surface_mesher_regular_edges' bad edges) and walks them in handle order, which for handles
// without a time stamp is their heap address: the same points gave another mesh after any change
// of the process's allocation history (another build of the same code, an environment tunable).
// With a stamp, CGAL's Compact_container orders handles by creation (as Mesh_3 does), and the
// mesh depends only on the input. ContourTriangulation is CGAL's
// Surface_mesh_default_triangulation_3_generator with these bases.
template <class Base>
class Time_stamped : public Base {
 public:
  using Has_timestamp = CGAL::Tag_true;
  template <class TDS>
  struct Rebind_TDS {
    using Other = Time_stamped<typename Base::template Rebind_TDS<TDS>::Other>;
  };
  using Base::Base;
  std::size_t time_stamp() const { return time_stamp_; }
  void set_time_stamp(const std::size_t& ts) { time_stamp_ = ts; }

 private:
  std::size_t time_stamp_ = std::size_t(-1);
};
using ContourKernel = CGAL::Robust_circumcenter_traits_3<pipeline::Kernel>;
using ContourTriangulation = CGAL::Delaunay_triangulation_3<
    ContourKernel,
    CGAL::Triangulation_data_structure_3<
        Time_stamped<CGAL::Surface_mesh_vertex_base_3<ContourKernel>>,
        CGAL::Delaunay_triangulation_cell_base_with_circumcenter_3<
            ContourKernel, Time_stamped<CGAL::Surface_mesh_cell_base_3<ContourKernel>>>>>;

// Mean distance to the 6 nearest neighbours: the spacing CGAL's Poisson reconstruction uses.
double poisson_spacing(const std::vector<PN>& pn) {
  return internal::average_spacing(pn, 6);
}

// Keeps a seeded pseudo-random subset of about `keep_points` of the points, in their order.
// A random subset of a scan is a scan of the same surface at a lower density, with the same
// noise, holes and outlier share; no CGAL function does this reproducibly
// (CGAL::random_simplify_point_set shuffles with std::rand's global state, which is neither
// seeded here nor safe when two reconstructions run in parallel, as in the acceptance test).
void random_subset(std::vector<PN>& pn, std::size_t keep_points) {
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double keep = double(keep_points) / double(pn.size());
  std::size_t n = 0;
  for (std::size_t i = 0; i < pn.size(); ++i)
    if (u(rng) < keep) pn[n++] = pn[i];
  pn.resize(n);
}

// CGAL::poisson_surface_reconstruction_delaunay, written out (the same calls and criteria) for
// two reasons: (1) the conjugate-gradient tolerance: the convenience function keeps Eigen's
// default, machine epsilon, so CG iterates far below any accuracy the contouring can use;
// (2) the step log shows the implicit function (Delaunay refinement + solve) and the
// contouring separately.
bool poisson_reconstruction(const std::vector<PN>& pn, double spacing_mm, double sm_distance_ratio,
                            double solver_tolerance, SurfaceMesh& mesh, StepClock& clock) {
  using Kernel = pipeline::Kernel;
  using Function = CGAL::Poisson_reconstruction_function<Kernel>;
  using Solver = CGAL::Eigen_solver_traits<
      Eigen::ConjugateGradient<CGAL::Eigen_sparse_symmetric_matrix<double>::EigenType>>;
  using STr = ContourTriangulation;
  using C2t3 = CGAL::Surface_mesh_complex_2_in_triangulation_3<STr>;
  using Surface = CGAL::Implicit_surface_3<Kernel, Function>;
  clock.start("Poisson implicit function (Delaunay refinement, CG solve) of " + std::to_string(pn.size()) + " points");
  Function function(pn.begin(), pn.end(), PointMap(), NormalMap());
  Solver solver;
  solver.solver().setTolerance(solver_tolerance);
  if (!function.compute_implicit_function(solver)) return false;
  // Eigen_solver_traits shares its Eigen solver between copies, so this is the solve just done
  char line[96];
  std::snprintf(line, sizeof line, "  conjugate gradient: %ld iterations, relative residual %.1e",
                long(solver.solver().iterations()), double(solver.solver().error()));
  pipeline::log("reconstruct", line);
  clock.start("Poisson contouring");
  const Point inner = function.get_inner_point();
  const auto bsphere = function.bounding_sphere();
  const double radius = std::sqrt(CGAL::to_double(bsphere.squared_radius()));
  const double sm_sphere_radius = 5.0 * radius;
  const double sm_dichotomy_error = sm_distance_ratio * spacing_mm / 1000.0;
  Surface surface(function, Kernel::Sphere_3(inner, sm_sphere_radius * sm_sphere_radius),
                  sm_dichotomy_error / sm_sphere_radius);
  CGAL::Surface_mesh_default_criteria_3<STr> criteria(20.0, 30.0 * spacing_mm, sm_distance_ratio * spacing_mm);
  STr tr;
  C2t3 c2t3(tr);
  CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_with_boundary_tag());
  if (tr.number_of_vertices() == 0) return false;
  CGAL::facets_in_complex_2_to_triangle_mesh(c2t3, mesh);
  return true;
}

// Builds an oriented Surface_mesh from the triangles of an interpolating reconstruction.
// The triangles are put in a canonical form first (each one's indices ascending, the list
// sorted): advancing front gives the same triangles in an order, and with orientations, that
// depend on the heap's addresses (the generated onesize cup, under reconstruct_cli's heap
// layouts), and every later step (orientation, repair, remeshing) follows face order. The
// orientation is the soup orientation's and orient_like_normals' anyway.
SurfaceMesh mesh_from_triangles(const std::vector<Point>& pts, std::vector<std::array<std::size_t, 3>> tris) {
  for (auto& t : tris) std::sort(t.begin(), t.end());
  std::sort(tris.begin(), tris.end());
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

// Cuts out what Poisson made where the scan has no points: every face with a vertex farther
// than `max_distance_mm` from all denoised points. Poisson closes a scan hole with the smooth
// surface its implicit function happens to have there, which bulges or sags over curved places
// (an 18 mm hole over the NIOSH large eye socket: 2.6 mm off); repair then fills the hole with
// CGAL's fairing (fill_holes.cpp, tangent-continuous with the scanned surface around it), which
// continues the surface's curvature across the hole. Faces are also removed around a vertex
// the cut would leave with two separate fans (a pinch), so the rest stays a manifold mesh.
// Returns the number of faces removed; the mesh is rebuilt without them.
std::size_t cut_unsupported_faces(SurfaceMesh& mesh, const internal::PointTree& tree, double max_distance_mm) {
  std::vector<char> far(mesh.number_of_vertices(), 0);
  const double max2 = max_distance_mm * max_distance_mm;
  for (auto v : mesh.vertices()) far[std::size_t(v)] = tree.nearest(mesh.point(v), 1).begin()->second > max2;
  std::vector<char> cut(mesh.number_of_faces(), 0);
  std::size_t n_cut = 0;
  for (auto f : mesh.faces())
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      if (far[std::size_t(v)]) {
        cut[std::size_t(f)] = 1, ++n_cut;
        break;
      }
  if (n_cut == 0) return 0;
  // a vertex whose ring alternates kept / cut more than once would be pinched: cut its ring
  for (bool changed = true; changed;) {
    changed = false;
    for (auto v : mesh.vertices()) {
      int switches = 0;
      bool any_kept = false;
      for (auto h : CGAL::halfedges_around_target(mesh.halfedge(v), mesh)) {
        const auto f = mesh.face(h), g = mesh.face(mesh.opposite(mesh.next(h)));
        const bool f_cut = f == SurfaceMesh::null_face() || cut[std::size_t(f)];
        const bool g_cut = g == SurfaceMesh::null_face() || cut[std::size_t(g)];
        any_kept |= !f_cut;
        switches += f_cut != g_cut;
      }
      if (!any_kept || switches <= 2) continue;
      for (auto f : CGAL::faces_around_target(mesh.halfedge(v), mesh))
        if (f != SurfaceMesh::null_face() && !cut[std::size_t(f)]) cut[std::size_t(f)] = 1, ++n_cut, changed = true;
    }
  }
  std::vector<Point> points;
  std::vector<std::array<std::size_t, 3>> faces;
  std::vector<std::size_t> index(mesh.number_of_vertices(), std::size_t(-1));
  for (auto f : mesh.faces()) {
    if (cut[std::size_t(f)]) continue;
    std::array<std::size_t, 3> tri{};
    int i = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      std::size_t& id = index[std::size_t(v)];
      if (id == std::size_t(-1)) id = points.size(), points.push_back(mesh.point(v));
      tri[i++] = id;
    }
    faces.push_back(tri);
  }
  SurfaceMesh kept;
  PMP::polygon_soup_to_polygon_mesh(points, faces, kept);
  mesh = std::move(kept);
  return n_cut;
}

// Denoise and remove spikes: each point is projected onto the jet (quadric) fitted to its k
// neighbours (CGAL). A spike (a point several mm off the surface) stays near its neighbours in
// k-NN distance, so outlier removal misses it, but its projection moves it by its height:
// points moved by more than 4 robust standard deviations (1.4826 × median move) are removed,
// the others keep their denoised position and their normal. Returns the number removed.
std::size_t jet_smooth_and_despike(std::vector<PN>& pn, unsigned k, std::vector<Point>* unsmoothed = nullptr) {
  if (pn.size() <= k) return 0;
  std::vector<PN> smoothed = pn;
  internal::jet_smooth(smoothed, k);
  std::vector<double> move(pn.size());
  for (std::size_t i = 0; i < pn.size(); ++i) move[i] = std::sqrt(CGAL::squared_distance(pn[i].first, smoothed[i].first));
  const double limit = internal::spike_move_limit_mm(move);
  std::vector<PN> kept;
  kept.reserve(pn.size());
  if (unsmoothed) unsmoothed->clear();
  for (std::size_t i = 0; i < pn.size(); ++i)
    if (move[i] <= limit) {
      kept.push_back({smoothed[i].first, pn[i].second});
      if (unsmoothed) unsmoothed->push_back(pn[i].first);
    }
  const std::size_t removed = pn.size() - kept.size();
  pn.swap(kept);
  return removed;
}

// Normals of a thin closed shell (respirator cups: wall 1.5 mm = 2–2.5 point spacings, noise
// 0.2 mm). A neighbourhood large enough for a stable normal reaches across the wall, so jet
// smoothing would pull both sides onto the mid-surface, and MST orientation gives both sides
// the SAME normal (their tangent planes are parallel; the inner side's normals then point into
// the wall and Poisson / orientation fail). No CGAL function separates the two sides of a thin
// wall, so it is done here:
//  1. jet normals over both sides = normals of the mid-surface, oriented by MST (right for the
//     mid-surface, a single sheet);
//  2. each point's 2k neighbours, projected on that normal, form two clusters (the two sides)
//     when the wall is thin: exact 1-D 2-means on the sorted projections; the point is on the
//     side whose cluster it is nearer to (its own projection is 0). Clusters closer than 4
//     pooled standard deviations (one side only in reach: thick wall, rim) leave it undecided;
//  3. the shell's outward normal is +normal on the upper side and −normal on the lower one;
//     undecided points are dropped;
//  4. only the inner side (the concave one, toward the face) is kept, jet-smoothed and
//     despiked on its own, its normals re-estimated (flipped to agree with step 3). Measured on
//     the generated onesize cup: Poisson on both separated sides gave a closed surface of
//     genus 143 (tunnels through the 1.4 mm wall) with 1361 self-intersecting faces; the inner
//     side alone is one open sheet whose border is the rim, which advancing front keeps.
// Returns false (pn untouched except for MST drops) when fewer than half the points see two
// sides: the scan is not a thin shell, and the MST normals are used as for heads.
bool orient_thin_shell(std::vector<PN>& pn, unsigned k, ReconstructStats& st) {
  internal::jet_normals(pn, k);
  internal::orient_normals(pn, k, 0.0);  // CGAL's weights: this is the mid-surface, a single sheet
  using Traits = CGAL::Search_traits_3<pipeline::Kernel>;
  using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;
  std::vector<Point> pts(pn.size());
  for (std::size_t i = 0; i < pn.size(); ++i) pts[i] = pn[i].first;
  const Search::Tree tree(pts.begin(), pts.end());
  const unsigned ks = 2 * k;
  std::vector<int> side(pn.size(), 0);
  std::vector<double> t, separations;
  for (std::size_t i = 0; i < pn.size(); ++i) {
    const Search search(tree, pn[i].first, ks);
    // Plane of the neighbourhood (PCA over both sides: the mid-plane), oriented like the MST
    // normal. A jet (quadric) fitted across the two sides tilts; a plane does not.
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> q;
    for (const auto& nb : search) q.emplace_back(nb.first.x(), nb.first.y(), nb.first.z());
    for (const auto& x : q) mean += x / double(q.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto& x : q) cov += (x - mean) * (x - mean).transpose();
    Eigen::Vector3d m = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);
    const Vector& mst = pn[i].second;
    if (m.x() * mst.x() + m.y() * mst.y() + m.z() * mst.z() < 0) m = -m;
    pn[i].second = Vector(m.x(), m.y(), m.z());
    const Eigen::Vector3d p0(pn[i].first.x(), pn[i].first.y(), pn[i].first.z());
    t.clear();
    for (const auto& x : q) t.push_back((x - p0).dot(m));
    std::sort(t.begin(), t.end());
    const std::size_t n = t.size();
    if (n < 8) continue;
    std::vector<double> s1(n + 1, 0), s2(n + 1, 0);  // prefix sums of t and t²
    for (std::size_t j = 0; j < n; ++j) s1[j + 1] = s1[j] + t[j], s2[j + 1] = s2[j] + t[j] * t[j];
    double best = 1e300;
    std::size_t split = 0;
    const std::size_t min_cluster = n / 6;  // a side holds ≥ 1/6 of the neighbours (geometry: ≥ 1/4)
    for (std::size_t j = min_cluster; j + min_cluster <= n; ++j) {
      const double a = s1[j], b = s1[n] - s1[j];
      const double sse = (s2[j] - a * a / double(j)) + (s2[n] - s2[j] - b * b / double(n - j));
      if (sse < best) best = sse, split = j;
    }
    if (split == 0) continue;
    const double lo = s1[split] / double(split), hi = (s1[n] - s1[split]) / double(n - split);
    const double sd = std::sqrt(std::max(0.0, best) / double(n - 2));
    if (hi - lo < 4.0 * sd) continue;
    side[i] = (0.0 - lo < hi - 0.0) ? -1 : +1;
    separations.push_back(hi - lo);
  }
  if (separations.size() * 2 < pn.size()) return false;
  std::vector<PN> sides[2];
  for (std::size_t i = 0; i < pn.size(); ++i)
    if (side[i] != 0) sides[side[i] > 0].push_back({pn[i].first, side[i] * pn[i].second});
  st.outliers_removed += pn.size() - sides[0].size() - sides[1].size();
  std::nth_element(separations.begin(), separations.begin() + long(separations.size() / 2), separations.end());
  st.wall_mm = separations[separations.size() / 2];
  // 4. Keep the inner side. The centroid of a dome's points lies in its hollow, so the inner
  //    side's outward normals (away from the wall) point toward it and the outer side's away.
  Vector centroid(0, 0, 0);
  for (const auto& s : sides)
    for (const auto& x : s) centroid = centroid + (x.first - CGAL::ORIGIN) / double(sides[0].size() + sides[1].size());
  double toward[2] = {0, 0};
  for (int j = 0; j < 2; ++j)
    for (const auto& x : sides[j]) toward[j] += (CGAL::ORIGIN + centroid - x.first) * x.second;
  std::vector<PN> inner = std::move(sides[toward[1] > toward[0] ? 1 : 0]);
  st.outer_side_points = sides[toward[1] > toward[0] ? 0 : 1].size();
  st.outliers_removed += jet_smooth_and_despike(inner, k);
  pn.clear();
  if (inner.size() <= k) return true;
  std::vector<PN> renormal = inner;
  internal::jet_normals(renormal, k);
  for (std::size_t i = 0; i < inner.size(); ++i) {
    const Vector& n = renormal[i].second;
    pn.push_back({inner[i].first, n * inner[i].second < 0 ? -n : n});
  }
  return true;
}

// Advancing-front priority (CGAL's documented customisation point): CGAL's default (smallest
// Delaunay radius first) plus a veto of facets with an edge longer than `max_edge_mm`. Without
// it, the front closes concave notches of an open border with long chords: on the generated
// onesize cup a 12 mm chord across the nose notch of the rim left the surface 3 mm off the
// cup after remeshing. Vetoed gaps inside the sheet become holes that repair fills with fairing.
struct ShortEdgesFirst {
  double max_edge_mm;
  template <typename AdvancingFront, typename CellHandle>
  double operator()(const AdvancingFront& adv, CellHandle& c, const int& index) const {
    for (int a = 1; a <= 3; ++a) {
      const auto& p = c->vertex((index + a) % 4)->point();
      const auto& q = c->vertex((index + a % 3 + 1) % 4)->point();
      if (CGAL::squared_distance(p, q) > max_edge_mm * max_edge_mm) return adv.infinity();
    }
    return adv.smallest_radius_delaunay_sphere(c, index);
  }
};

// CGAL::advancing_front_surface_reconstruction(b, e, out, priority, ...), written out with
// time-stamped vertex and cell bases (as the contouring's triangulation above): the front keeps
// its candidate facets in std::sets ordered by priority and then by cell handle, the heap
// address without a time stamp, so equal priorities were taken in an address order (the
// generated onesize cup: 43,562 triangles, or 43,560 under either GLIBC_TUNABLES of
// reconstruct_cli's heap-layout test).
template <class Priority>
void advancing_front_triangles(const std::vector<Point>& pts, const Priority& priority, double radius_ratio_bound,
                               double beta, std::vector<std::array<std::size_t, 3>>& tris) {
  using Kernel = pipeline::Kernel;
  using Vb = Time_stamped<CGAL::Advancing_front_surface_reconstruction_vertex_base_3<Kernel>>;
  using Cb = Time_stamped<CGAL::Advancing_front_surface_reconstruction_cell_base_3<Kernel>>;
  using Triangulation = CGAL::Delaunay_triangulation_3<Kernel, CGAL::Triangulation_data_structure_3<Vb, Cb>>;
  using Reconstruction = CGAL::Advancing_front_surface_reconstruction<Triangulation, Priority>;
  // Auto_count_cc numbers the points in input order (the vertex ids of the output triples); its
  // converter is the identity here, since the points are already in the triangulation's kernel
  using Convert = CGAL::Cartesian_converter<Kernel, Kernel>;
  Convert convert;
  Triangulation dt(boost::make_transform_iterator(pts.begin(), CGAL::AFSR::Auto_count_cc<Kernel::Point_3, Convert>(convert)),
                   boost::make_transform_iterator(pts.end(), CGAL::AFSR::Auto_count_cc<Kernel::Point_3, Convert>(convert)));
  Reconstruction reconstruction(dt, priority);
  reconstruction.run(radius_ratio_bound, beta);
  CGAL::write_triple_indices(std::back_inserter(tris), reconstruction);
}

}  // namespace

ScanKind parse_scan_kind(const std::string& name) {
  if (name == "head") return ScanKind::head;
  if (name == "respirator") return ScanKind::respirator;
  throw pipeline::Error(pipeline::ErrorKind::usage, "--kind: '" + name + "', expected head or respirator");
}
std::string scan_kind_name(ScanKind k) { return k == ScanKind::head ? "head" : "respirator"; }
double expected_size_mm(ScanKind k) {
  return k == ScanKind::head ? pipeline::head_extent_mm : pipeline::respirator_extent_mm;
}

void KindAndUnitOptions::add_to(pipeline::Cli& cli, const std::string& kind_help) {
  cli.option("-k", "--kind", &kind_name, kind_help);
  cli.option("-u", "--unit", &unit_name, "unit of the input: auto, mm, cm, m, in");
}
ScanKind KindAndUnitOptions::kind() const { return parse_scan_kind(kind_name); }
pipeline::ScanReadOptions KindAndUnitOptions::read_options() const {
  pipeline::ScanReadOptions read;
  read.unit = pipeline::parse_unit(unit_name);
  read.expected_size_mm = expected_size_mm(kind());
  return read;
}

std::string KindAndUnitOptions::describe_unit(const pipeline::Scan& scan) const {
  const double box_mm = pipeline::largest_extent(scan.is_mesh ? scan.soup.points : scan.cloud.points);
  std::string text = pipeline::describe_unit(scan.unit, pipeline::parse_unit(unit_name) == pipeline::Unit::automatic,
                                             scan.extent_mm, kind_name, expected_size_mm(kind()));
  if (box_mm > scan.extent_mm)
    text += "; a few far points stretch the box to " + pipeline::format_number(box_mm) +
            " mm: outliers or debris, removed with them";
  for (const std::string& note : scan.notes) text += "; " + note;
  return text;
}

void KindAndUnitOptions::require_plausible_size(const pipeline::Scan& scan, const std::string& path) const {
  if (pipeline::parse_unit(unit_name) != pipeline::Unit::automatic)
    pipeline::require_forced_unit_plausible(path, scan.unit, scan.extent_mm, kind_name, expected_size_mm(kind()));
}

ReconstructMethod parse_reconstruct_method(const std::string& name, ScanKind kind) {
  // respirators: the inner side of the cup is an open sheet (orient_thin_shell), which
  // advancing front keeps open and Poisson would close into a blob
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
  // CGAL draws from its default generator (thread-local, seeded from the clock) inside the
  // reconstruction; seeded here so the same scan gives the same mesh in every run and thread
  CGAL::get_default_random() = CGAL::Random(20261124);
  if (cloud.points.size() < min_points)
    throw pipeline::bad_input("point cloud", std::to_string(cloud.points.size()) +
                                                 " points are too few to define a surface, expected at least " +
                                                 std::to_string(min_points));
  // A scan's normals are used only when every point has one: points without one (read as zero
  // vectors) went into Poisson as they were. Otherwise all are estimated from the points.
  std::size_t zero_normals = 0;
  if (cloud.normals.size() == cloud.points.size())
    for (const Vector& n : cloud.normals) zero_normals += n.squared_length() < 1e-12;
  bool has_normals = cloud.normals.size() == cloud.points.size() && zero_normals == 0;
  if (zero_normals > 0)
    pipeline::log("reconstruct", std::to_string(zero_normals) + " of " + std::to_string(cloud.points.size()) +
                                     " points have no normal: all normals are estimated from the points instead");
  // A respirator's wall is scanned from both sides 1-2 mm apart: its points go through the
  // thin-shell separation whatever normals the scan brings. With its own normals kept, advancing
  // front meshed both sides into one surface; repair left it with 57 handles, and fit crashed on
  // it (sweep K, the generator's clean cup as points with outward normals).
  const bool thin_shell_candidate = kind == ScanKind::respirator;
  if (thin_shell_candidate && has_normals) {
    pipeline::log("reconstruct", "the scan's normals are not used for a respirator: its two-sided wall is oriented "
                                 "from the points (thin-shell separation)");
    has_normals = false;
  }
  std::vector<PN> pn(cloud.points.size());
  for (std::size_t i = 0; i < pn.size(); ++i) pn[i] = {cloud.points[i], has_normals ? cloud.normals[i] : Vector(0, 0, 0)};
  const unsigned k = unsigned(opt.neighbors);
  // Normals that do not follow the points' surface are estimated afresh, like missing ones: all
  // (0, 0, 1) on a head scan took Poisson 5 minutes and 3.6 GB to a CGAL assertion. Checked at
  // 2,000 points (the k-d tree over all points costs most of it: ~1 s on a million);
  // see share_of_normals_along_surface.
  if (has_normals) {
    const double along = internal::share_of_normals_along_surface(pn, k, 2000);
    if (along < min_share_of_normals_along_surface) {
      pipeline::log("reconstruct", "the scan's normals do not follow its surface (" +
                                       std::to_string(int(std::lround(100 * along))) +
                                       " % within 45 deg of it): all normals are estimated from the points instead");
      has_normals = false;
      for (auto& p : pn) p.second = Vector(0, 0, 0);
    } else if (const double away = share_of_normals_away_from_centre(pn);
               away > max_share_of_unoriented_normals_away || away < 1 - max_share_of_unoriented_normals_away) {
      // said, as their estimation is: a scanner's bad normals were trusted with no line (sweep O)
      pipeline::log("reconstruct", "the scan's own normals are used (" + std::to_string(int(std::lround(100 * along))) +
                                       " % within 45 deg of its surface, " + std::to_string(int(std::lround(100 * away))) +
                                       " % pointing away from its centre)");
    } else {
      pipeline::log("reconstruct", "the scan's normals are not oriented (" + std::to_string(int(std::lround(100 * away))) +
                                       " % point away from its centre, the others toward it): they are oriented afresh "
                                       "from the points");
      has_normals = false;
      for (auto& p : pn) p.second = Vector(0, 0, 0);
    }
  }
  pipeline::Progress progress("reconstruct", 0);
  StepClock clock(progress, st);

  // 1. Thin dense scans (bounds time and memory; the output is remeshed anyway). A scan of more
  //    than opt.density_reference_points points is first cut to a random subset of that many,
  //    i.e. to the density at which the accuracy is measured, so the cost of every later step
  //    no longer grows with the scanner's density (1M points on NIOSH medium: the 0.8 mm grid
  //    alone left 428k points and Poisson took 119 s). Why not a coarser grid instead: a grid
  //    cell chosen to leave the same number of points was 1.39 mm there (the noise band fills
  //    more cells when dense) and merged the two sides of the ears: p95 0.60 mm, Hausdorff
  //    9.6 mm at the ear, 10 holes for repair (bench_scan2cad, 1M points). Then the grid.
  if (opt.density_reference_points > 0 && pn.size() > opt.density_reference_points && !thin_shell_candidate) {
    clock.start("random subset of " + std::to_string(opt.density_reference_points) + " points");
    random_subset(pn, opt.density_reference_points);
  }
  if (opt.simplify_cell_mm > 0) {
    clock.start("grid simplification");
    pn.erase(CGAL::grid_simplify_point_set(pn, opt.simplify_cell_mm, CGAL::parameters::point_map(PointMap())), pn.end());
  }
  st.points_after_thinning = pn.size();
  pipeline::log("reconstruct", "  " + std::to_string(st.input_points) + " -> " + std::to_string(pn.size()) + " points");

  // 2. Outliers: mean k-NN distance above outlier_factor × the cloud's average spacing.
  clock.start("outlier removal");
  const std::size_t before = pn.size();
  internal::remove_points_beyond_spacing(pn, k, opt.outlier_factor);
  // Isolated points: the k-NN test above misses a lone outlier beside a scan hole, whose 24
  // neighbours lie on one side at 3-5 mm like a hole's rim points' do (generated large head,
  // 200k points: one 3.2 mm off the surface inside a nape hole kept a lip of Poisson's fill
  // there, 1.5 mm off after repair). Its few nearest neighbours are 4-6 spacings away where a
  // surface point's are about one (even on a thin ear rim): the same test on 4 neighbours.
  const unsigned k_isolated = 4;
  internal::remove_points_beyond_spacing(pn, k_isolated, opt.outlier_factor);
  st.outliers_removed = before - pn.size();
  if (opt.remove_support) {
    clock.start("support plane (a table or turntable under the object)");
    const SupportPlane support = remove_support_plane(pn);
    st.support_points_removed = support.points_removed;
    if (support.found)
      pipeline::log("reconstruct", support.removal_line(support.points_removed, "points"));
  }
  if (pn.size() < min_points)
    throw pipeline::bad_input("point cloud", "only " + std::to_string(pn.size()) +
                                                 " points left after outlier removal, expected at least " +
                                                 std::to_string(min_points));
  if (opt.min_extent_mm > 0 || opt.max_extent_mm > 0) {
    std::vector<Point> kept(pn.size());
    std::transform(pn.begin(), pn.end(), kept.begin(), [](const PN& p) { return p.first; });
    const double extent_mm = pipeline::largest_extent(kept);
    if (extent_mm < opt.min_extent_mm)
      throw pipeline::bad_input("point cloud", "without its outliers it spans " + pipeline::format_number(extent_mm) +
                                                   " mm, under the " + pipeline::format_number(opt.min_extent_mm) +
                                                   " mm of the smallest " + scan_kind_name(kind) + ": " +
                                                   pipeline::wrong_size_question(false));
    if (opt.max_extent_mm > 0 && extent_mm > opt.max_extent_mm)
      throw pipeline::bad_input("point cloud", "without its outliers it spans " + pipeline::format_number(extent_mm) +
                                                   " mm, over the " + pipeline::format_number(opt.max_extent_mm) +
                                                   " mm of the largest " + scan_kind_name(kind) + ": " +
                                                   pipeline::wrong_size_question(true));
  }
  // Points on a plane or a line: CGAL 5.5's Poisson crashes when its Delaunay triangulation is
  // flat and never finishes contouring when it is nearly so (a plane with 0.001 mm of noise ran
  // for over 5 minutes). Across its thinnest axis a head spreads 0.64 times as far as along its
  // longest (NIOSH medium) and a generated cup 0.48 times (pipeline/principal_spreads.h).
  // Checked after the outlier removal: 1 % of outliers in a box would hide a plane.
  if (const std::string why = pipeline::why_flat(
          pipeline::principal_spreads(pn, [](const PN& x) -> const Point& { return x.first; }), "the points");
      !why.empty())
    throw pipeline::bad_input("point cloud", why);
  const double on_surface =
      internal::share_of_points_on_a_surface(pn, surface_check_neighbors, 2000, surface_check_min_quality);
  if (on_surface < min_share_of_points_on_a_surface)
    throw pipeline::bad_input("point cloud", "the points fill a volume instead of lying on a surface (" +
                                                 std::to_string(int(std::lround(100 * on_surface))) +
                                                 " % of them have their neighbours near a plane, on a scanned "
                                                 "surface over 90 % do): noise, not a scan");

  // 3. Denoise and remove spikes (jet_smooth_and_despike). A thin respirator shell is
  //    smoothed side by side in step 4 instead (its neighbourhoods span both sides).
  // The refit of step 4 starts again from the unsmoothed positions, and Poisson's vertices are
  // projected onto them (step 6): they are kept beside pn, unsmoothed[i] for pn[i] (a second
  // grid of the denoised points would break that pairing, so neither is done with one).
  const bool refit = !thin_shell_candidate && !has_normals && opt.refit_on_own_side && opt.denoised_cell_mm <= 0;
  const bool project_unsmoothed = !thin_shell_candidate && opt.method == ReconstructMethod::poisson &&
                                  opt.projection_max_move_mm > 0 && opt.projection_onto_unsmoothed &&
                                  opt.denoised_cell_mm <= 0;
  const bool keep_unsmoothed = refit || project_unsmoothed;
  std::vector<Point> unsmoothed;
  std::vector<char> thin_part;  // per point of pn after step 4: the other side of a thin part in reach
  if (!thin_shell_candidate) {
    clock.start("jet smoothing and spike removal");
    st.outliers_removed += jet_smooth_and_despike(pn, k, keep_unsmoothed ? &unsmoothed : nullptr);
  }

  // 3b. The denoised points lie on the surface: thin them again to the grid. Before smoothing
  //     the noise spreads them through a band (1M points, 0.3 mm noise: 428k points stay after
  //     the first 0.8 mm grid); after it, one point per surface cell is left, which bounds the
  //     cost of the normals, MST and Poisson by the surface area instead of the point count.
  if (!thin_shell_candidate && opt.denoised_cell_mm > 0) {
    clock.start("grid simplification of the denoised points");
    pn.erase(CGAL::grid_simplify_point_set(pn, opt.denoised_cell_mm, CGAL::parameters::point_map(PointMap())), pn.end());
  }

  // 4. Normals: jet fitting + minimum-spanning-tree orientation (CGAL), when the scan has none.
  if (thin_shell_candidate) {
    clock.start("thin-shell normals: both sides separated, each smoothed");
    st.thin_shell = orient_thin_shell(pn, k, st);
    st.normals_estimated = true;
    if (!st.thin_shell) st.outliers_removed += jet_smooth_and_despike(pn, k);  // one side: as for heads
  } else if (!has_normals) {
    clock.start("normal estimation (jet fitting)");
    internal::jet_normals(pn, k);
    clock.start("normal orientation (minimum spanning tree)");
    // points the tree cannot reach are dropped: their normal would be a coin toss
    std::vector<std::size_t> reached;
    const std::size_t before_orientation = pn.size();
    const std::size_t unreached =
        internal::orient_normals(pn, k, opt.orientation_crossing_weight, keep_unsmoothed ? &reached : nullptr);
    // The tree reaches one connected piece: of two heads 400 mm apart one was meshed and the other
    // dropped without a word. Stray clusters the outlier removal left are a few points.
    if (double(unreached) > max_unreached_share * double(before_orientation))
      throw pipeline::bad_input("point cloud", std::to_string(int(std::lround(100.0 * double(unreached) /
                                                                             double(before_orientation)))) +
                                                   " % of the points are apart from the rest (not within " +
                                                   std::to_string(k) + " neighbours of it): two objects, or a scan "
                                                   "in pieces? reconstruct meshes one connected surface");
    st.normals_estimated = true;
    if (keep_unsmoothed) {
      for (std::size_t i = 0; i < reached.size(); ++i) unsmoothed[i] = unsmoothed[reached[i]];
      unsmoothed.resize(reached.size());
    }
    if (refit) {
      clock.start("jet smoothing and normals again, each point on its own side");
      const internal::RefitStats rs = internal::refit_on_own_side(pn, unsmoothed, k, opt.refit_min_cos, &thin_part);
      st.outliers_removed += rs.spikes;
      pipeline::log("reconstruct", "  " + std::to_string(rs.refitted) + " points with the other side in reach refitted, " +
                                       std::to_string(rs.too_few) + " kept (too few on their side), " +
                                       std::to_string(rs.spikes) + " spikes dropped");
    }
  }
  // spacing = mean distance to the 6 nearest neighbours (CGAL's Poisson convention)
  clock.start("spacing");
  st.spacing_mm = poisson_spacing(pn);
  st.points_used = pn.size();
  if (kind == ScanKind::head && opt.max_head_spacing_mm > 0 && st.spacing_mm > opt.max_head_spacing_mm)
    throw pipeline::bad_input("point cloud", "its points are " + pipeline::format_number(std::round(st.spacing_mm * 100) / 100) +
                                                 " mm apart (mean spacing to 6 neighbours), too sparse for a head: the "
                                                 "ears, folds about 1 mm thick, are lost between them, and the tragia "
                                                 "found without them come out tens of mm off; a head scan needs points "
                                                 "at most " + pipeline::format_number(opt.max_head_spacing_mm) +
                                                 " mm apart (a whole adult head: about 30,000 points or more), or give its mesh "
                                                 "(--max-spacing-mm changes the limit)");

  // 5. Reconstruction.
  SurfaceMesh mesh;
  if (opt.method == ReconstructMethod::poisson) {
    // Poisson's input may be thinned (opt.poisson_cell_mm): its implicit function only has to
    // get the topology and the rough shape right, because the projection below moves its
    // vertices onto all the denoised points. Thinned after the normals, which need the dense
    // neighbourhoods (thinned before them, the ears' two sides mix: see denoised_cell_mm).
    std::vector<PN> thinned;
    double poisson_spacing_mm = st.spacing_mm;
    if (opt.poisson_cell_mm > 0) {
      clock.start("grid simplification of Poisson's input");
      // Points of thin parts (the other side in reach, flagged by the refit) all go to Poisson:
      // a cell of the grid holds both sides of a fin under 2 mm across and keeps one point. NIOSH
      // large's ear fin, distance of its top to Poisson's surface / after the projection: 2.60 /
      // 1.08 mm thinned, 1.79 / 0.57 mm with its points kept (README.md, session 14). About 700
      // points on a NIOSH scan, none on the generated heads.
      std::vector<PN> thin_points;
      if (opt.poisson_keep_thin_parts && thin_part.size() == pn.size()) {
        for (std::size_t i = 0; i < pn.size(); ++i) (thin_part[i] ? thin_points : thinned).push_back(pn[i]);
      } else {
        thinned = pn;
      }
      thinned.erase(CGAL::grid_simplify_point_set(thinned, opt.poisson_cell_mm, CGAL::parameters::point_map(PointMap())),
                    thinned.end());
      thinned.insert(thinned.end(), thin_points.begin(), thin_points.end());
      pipeline::log("reconstruct", "  " + std::to_string(thinned.size()) + " points for Poisson, of them " +
                                       std::to_string(thin_points.size()) + " of thin parts, not thinned");
      poisson_spacing_mm = poisson_spacing(thinned);
    }
    const std::vector<PN>& poisson_input = opt.poisson_cell_mm > 0 ? thinned : pn;
    // Contouring: facets within opt.poisson_distance_mm of the implicit surface (CGAL's default
    // 0.375 × spacing would be 0.3–0.6 mm here, above the accuracy asked for) and of radius
    // ≤ 30 × spacing; repair remeshes the result anyway.
    if (!poisson_reconstruction(poisson_input, poisson_spacing_mm,
                                // CGAL's surface mesher fails ("already inserted")
                                // below ~0.1 × spacing on sparse clouds
                                std::max(opt.poisson_distance_mm / poisson_spacing_mm, 0.1), opt.poisson_solver_tolerance,
                                mesh, clock))
      throw pipeline::algorithm_failed("point cloud", "Poisson reconstruction failed (normals inconsistent?)");
    if (CGAL::is_closed(mesh) && !PMP::is_outward_oriented(mesh)) PMP::reverse_face_orientations(mesh);
    const internal::PointTree tree(pn);
    if (opt.hole_cut_spacings > 0) {
      clock.start("cutting out Poisson's fill of the scan holes");
      st.faces_cut = cut_unsupported_faces(mesh, tree, opt.hole_cut_spacings * st.spacing_mm);
      pipeline::log("reconstruct", "  " + std::to_string(st.faces_cut) + " faces farther than " +
                                       pipeline::format_number(opt.hole_cut_spacings) + " spacings from the points removed");
    }
    if (opt.projection_max_move_mm > 0) {
      clock.start("projection of the Poisson vertices onto the points");
      // Only Poisson's own vertices are moved. Tried: remeshing the Poisson mesh to one point
      // spacing first (1 iteration of isotropic remeshing), so every facet gets projected
      // vertices: NIOSH large, 200k points, p95 0.212 mm instead of 0.189, Hausdorff 3.17
      // instead of 2.92 mm, and 10 s more CPU (many vertices each following its own fit's noise);
      // 3 passes with the vertex normals recomputed in between: Hausdorff 3.08 mm, p95 0.191
      const double sign = internal::point_normal_sign(mesh, pn, tree);
      const std::vector<pipeline::VertexIndex> all(mesh.vertices().begin(), mesh.vertices().end());
      // The points projected onto: by default the unsmoothed ones, each with its denoised
      // point's oriented normal, over opt.projection_neighbors. The jet smoothing has already
      // rounded every crease and tip once; a quadric over the smoothed points rounds them
      // again. Acceptance scans, Hausdorff / p95 [mm], smoothed (24) -> unsmoothed (64): NIOSH
      // large 1.823 / 0.188 -> 1.505 / 0.170, generated medium 0.943 / 0.168 -> 0.874 / 0.153;
      // 32 neighbours were too noisy (p95 0.198-0.212), 96 rounded the ear's front flap
      // (README.md, session 18).
      std::vector<PN> raw;
      if (project_unsmoothed && unsmoothed.size() == pn.size()) {
        raw.resize(pn.size());
        for (std::size_t i = 0; i < pn.size(); ++i) raw[i] = {unsmoothed[i], pn[i].second};
      }
      const std::vector<PN>& onto = raw.empty() ? pn : raw;
      const std::unique_ptr<internal::PointTree> raw_tree = raw.empty() ? nullptr : std::make_unique<internal::PointTree>(raw);
      const internal::PointTree& onto_tree = raw.empty() ? tree : *raw_tree;
      const unsigned k_onto = raw.empty() ? k : unsigned(opt.projection_neighbors);
      const internal::ProjectionStats ps = internal::project_onto_points(mesh, all, sign, onto, onto_tree, k_onto,
                                                                         st.spacing_mm, opt.projection_max_move_mm);
      st.projected_vertices = ps.moved;
      st.unprojected_vertices = ps.unsupported;
      st.projection_mean_mm = ps.mean_move_mm;
      st.projection_max_mm = ps.max_move_mm;
      char line[224];
      std::snprintf(line, sizeof line, "  %zu vertices moved (mean %.3f mm, max %.3f mm), %zu without support left",
                    ps.moved, ps.mean_move_mm, ps.max_move_mm, ps.unsupported);
      pipeline::log("reconstruct", line);
      if (opt.untangle_rounds > 0) {
        clock.start("untangling the faces the projection made cross");
        const internal::UntangleStats us = internal::untangle_crossings(
            mesh, sign, onto, onto_tree, k_onto, st.spacing_mm, opt.projection_max_move_mm, opt.untangle_rounds);
        std::snprintf(line, sizeof line,
                      "  %d rounds: %zu faces cut (%zu more in pieces they severed), %zu gaps filled, %zu patch "
                      "vertices projected, %zu crossing faces left",
                      us.rounds, us.faces_cut, us.piece_faces_removed, us.gaps_filled, us.vertices_projected,
                      us.crossing_left);
        pipeline::log("reconstruct", line);
      }
    }
  } else {
    clock.start(reconstruct_method_name(opt.method) + " reconstruction of " + std::to_string(pn.size()) + " points");
    std::vector<Point> pts(pn.size());
    std::vector<std::array<std::size_t, 3>> tris;
    if (opt.method == ReconstructMethod::advancing_front) {
      for (std::size_t i = 0; i < pn.size(); ++i) pts[i] = pn[i].first;
      advancing_front_triangles(pts, ShortEdgesFirst{opt.max_edge_spacings * st.spacing_mm}, 5.0, 0.52, tris);
    } else {
      CGAL::Scale_space_surface_reconstruction_3<pipeline::Kernel> ss;
      for (const auto& p : pn) ss.insert(p.first);
      ss.increase_scale(4, CGAL::Scale_space_reconstruction_3::Weighted_PCA_smoother<pipeline::Kernel>(k));
      ss.reconstruct_surface(CGAL::Scale_space_reconstruction_3::Advancing_front_mesher<pipeline::Kernel>(10 * st.spacing_mm));
      // The connectivity found at the coarse scale goes back onto the points as they were before
      // the scale-space smoothing (CGAL keeps their order): the smoothed points themselves lie
      // inside wherever the surface bends (4 weighted-PCA steps pulled a 50 mm sphere in by
      // 0.27 mm on average, the heads' p95 to 0.36-0.57 mm; reconstruct_test).
      for (std::size_t i = 0; i < pn.size(); ++i) pts[i] = pn[i].first;
      for (auto it = ss.facets_begin(); it != ss.facets_end(); ++it) tris.push_back({(*it)[0], (*it)[1], (*it)[2]});
    }
    if (tris.empty()) throw pipeline::algorithm_failed("point cloud", "reconstruction produced no triangles");
    mesh = mesh_from_triangles(pts, tris);
    orient_like_normals(mesh, pts, pn);
  }
  if (mesh.number_of_faces() == 0) throw pipeline::algorithm_failed("point cloud", "reconstruction produced no triangles");
  st.vertices = mesh.number_of_vertices();
  st.faces = mesh.number_of_faces();
  clock.stop();
  // step, not finish: the program has yet to write the mesh, and a failed write must not follow a "done"
  progress.step("reconstructed: " + std::to_string(st.faces) + " triangles from " + std::to_string(st.points_used) + " points");
  if (stats_out) *stats_out = st;
  return mesh;
}

}  // namespace scan2cad
