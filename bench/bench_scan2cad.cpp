// bench_scan2cad: reconstruct + repair of a simulated scan of a real surface, timed, with the
// distance of the result to that surface. Run under /usr/bin/time -v for peak memory:
//   /usr/bin/time -v build/bin/bench_scan2cad --points 1000000
//       --mesh ../shared/data/headforms/NIOSH_medium_20k.stl
// The scan is made by the project's generator library (sample, 3 holes of 10–20 mm, noise,
// outliers); the same code path as `generate_scan --from-mesh` then `reconstruct` and `repair`.
#include <chrono>
#include <cstdio>

#include "data/generator/scanner_artifacts.h"
#include "pipeline/atomic_write.h"
#include "pipeline/cli.h"
#include "pipeline/read_scan.h"
#include "pipeline/soup_to_mesh.h"
#include "pipeline/write_mesh.h"
#include "scan2cad/reconstruct.h"
#include "scan2cad/repair.h"
#include "scan2cad/surface_distance.h"

int main(int argc, char** argv) {
  std::string mesh_path, method_name = "auto", out_prefix;
  int points = 1000000, seed = 7;
  double noise = 0.3, outliers = 0.01, crossing = -1, cell = -1, denoised_cell = -1, pdist = -1, cg_tol = -1, projection = -1, hole_cut = -1, poisson_cell = -1;
  int density_points = -1, untangle = -1;
  bool thin_parts_thinned = false;
  scan2cad::RepairOptions ropt;
  pipeline::Cli cli("bench_scan2cad", "Times reconstruct + repair on a simulated scan of a mesh.");
  cli.option("-m", "--mesh", &mesh_path, "reference surface (STL/PLY/OFF/OBJ)", pipeline::required);
  cli.option("-n", "--points", &points, "surface samples", 1000, 50000000);
  cli.option("-N", "--noise-mm", &noise, "Gaussian noise sigma [mm]", 0, 10);
  cli.option("-f", "--outliers", &outliers, "outlier fraction", 0, 0.4);
  cli.option("-M", "--method", &method_name, "reconstruction method (auto, poisson, advancing_front, scale_space)");
  cli.option("-w", "--orientation-crossing-weight", &crossing, "MST cost of a link along the normals (-1: default)", -1, 100);
  double refit_min_cos = -2;
  bool no_refit = false;
  cli.flag("-R", "--no-own-side-refit", &no_refit, "keep the smoothing over plain neighbourhoods");
  cli.option("-r", "--own-side-min-cos", &refit_min_cos, "own-side refit: normals' cosine of a same-side neighbour (-2: default)", -2, 1);
  cli.option("-c", "--cell", &cell, "grid simplification cell [mm] (-1: default)", -1, 50);
  cli.option("-C", "--denoised-cell", &denoised_cell, "grid cell after smoothing [mm] (-1: default)", -1, 50);
  cli.option("-g", "--poisson-cell", &poisson_cell, "grid cell of Poisson's input after the normals [mm] (-1: default)", -1, 50);
  cli.option("-d", "--poisson-distance", &pdist, "Poisson accuracy [mm] (-1: default)", -1, 10);
  cli.option("-D", "--density-reference", &density_points, "thin denser scans to a scan of this many points, 0 = none (-1: default)", -1, 2000000000);
  cli.option("-T", "--cg-tolerance", &cg_tol, "Poisson CG relative tolerance (-1: default)", -1, 1);
  cli.option("-P", "--projection-max-move", &projection, "Poisson vertices onto the points: largest move [mm], 0 = off (-1: default)", -1, 50);
  cli.option("-H", "--hole-cut-spacings", &hole_cut, "cut Poisson faces this many spacings from the points, 0 = off (-1: default)", -1, 100);
  cli.flag("-G", "--poisson-thin-parts-thinned", &thin_parts_thinned, "Poisson: thin the points of thin parts too");
  cli.option("-U", "--untangle-rounds", &untangle, "rounds of refilling faces the projection made cross (-1: default)", -1, 20);
  bool onto_smoothed = false;
  cli.flag("-O", "--project-onto-smoothed", &onto_smoothed, "Poisson: project onto the jet-smoothed points");
  int projection_neighbors = -1;
  cli.option("-K", "--projection-neighbors", &projection_neighbors,
             "Poisson: neighbours of the projection onto the unsmoothed points (-1: default)", -1, 200);
  cli.option("-e", "--edge", &ropt.target_edge_mm, "repair target edge [mm]", 0, 50);
  cli.option("-s", "--smooth", &ropt.smoothing_iterations, "repair smoothing steps", 0, 100);
  cli.option("-t", "--smooth-time", &ropt.smoothing_time, "repair smoothing time step", 1e-9, 1);
  cli.option("-p", "--spike-factor", &ropt.spike_factor, "repair spike threshold (x mean one-ring radius)", 0.1, 1000);
  cli.option("-S", "--seed", &seed, "random seed", 0, 1 << 30);
  cli.option("-o", "--out", &out_prefix, "write PREFIX_reconstructed.ply and PREFIX_repaired.ply (optional)");
  return pipeline::run_main(cli, argc, argv, [&] {
    using clock = std::chrono::steady_clock;
    auto secs = [](clock::time_point a) { return std::chrono::duration<double>(clock::now() - a).count(); };
    // Checked before the work: `-o /proc/pre` failed after the whole reconstruct and repair.
    if (!out_prefix.empty())
      pipeline::require_writable_outputs({out_prefix + "_reconstructed.ply", out_prefix + "_repaired.ply"});
    // 1. Reference surface and simulated scan
    const auto scan_in = pipeline::read_scan(mesh_path);
    const auto reference = pipeline::soup_to_mesh(scan_in.soup);
    generator::ScanOptions so;
    so.points = std::size_t(points);
    so.noise_mm = noise;
    so.outliers.fraction = outliers;
    so.random_holes = 3;
    generator::Rng rng{std::uint64_t(seed)};
    std::vector<generator::Hole> holes;
    const auto cloud = generator::scan_surface(generator::triangles_of(scan_in.soup), so, rng, &holes);
    // where the scan has no points: the output there is a fill, not a reconstruction
    for (const auto& h : holes)
      std::printf("hole centre %.1f %.1f %.1f diameter %.1f mm\n", h.centre.x(), h.centre.y(), h.centre.z(),
                  2 * h.radius_mm);
    // 2. Reconstruct + repair, timed
    scan2cad::ReconstructOptions opt;
    opt.method = scan2cad::parse_reconstruct_method(method_name, scan2cad::ScanKind::head);
    if (crossing >= 0) opt.orientation_crossing_weight = crossing;
    opt.refit_on_own_side = !no_refit;
    if (refit_min_cos >= -1) opt.refit_min_cos = refit_min_cos;
    if (cell >= 0) opt.simplify_cell_mm = cell;
    if (denoised_cell >= 0) opt.denoised_cell_mm = denoised_cell;
    if (pdist > 0) opt.poisson_distance_mm = pdist;
    if (poisson_cell >= 0) opt.poisson_cell_mm = poisson_cell;
    if (density_points >= 0) opt.density_reference_points = std::size_t(density_points);
    if (cg_tol > 0) opt.poisson_solver_tolerance = cg_tol;
    if (projection >= 0) opt.projection_max_move_mm = projection;
    if (hole_cut >= 0) opt.hole_cut_spacings = hole_cut;
    opt.poisson_keep_thin_parts = !thin_parts_thinned;
    if (untangle >= 0) opt.untangle_rounds = untangle;
    opt.projection_onto_unsmoothed = !onto_smoothed;
    if (projection_neighbors > 0) opt.projection_neighbors = projection_neighbors;
    auto t0 = clock::now();
    scan2cad::ReconstructStats rs;
    const auto rec = scan2cad::reconstruct(cloud, scan2cad::ScanKind::head, opt, &rs);
    const double t_rec = secs(t0);
    pipeline::PolygonSoup soup;
    for (auto v : rec.vertices()) soup.points.push_back(rec.point(v));
    for (auto f : rec.faces()) {
      soup.polygons.emplace_back();
      for (auto v : CGAL::vertices_around_face(rec.halfedge(f), rec)) soup.polygons.back().push_back(std::size_t(v));
    }
    t0 = clock::now();
    scan2cad::RepairReport rr;
    const auto out = scan2cad::repair(soup, scan2cad::ScanKind::head, ropt, &rr);
    const double t_rep = secs(t0);
    for (const auto& s : rs.step_times)
      std::printf("step %-70s %7.1f s wall %7.1f s CPU\n", s.step.c_str(), s.wall_s, s.cpu_s);
    // 3. Quality
    if (!out_prefix.empty()) {
      pipeline::write_surface_mesh(out_prefix + "_reconstructed.ply", rec);
      pipeline::write_surface_mesh(out_prefix + "_repaired.ply", out);
    }
    const auto d = scan2cad::surface_distance(out, reference);
    std::printf("worst output point %.2f %.2f %.2f | worst reference point %.2f %.2f %.2f, nearest scan point %.2f mm "
                "from it\n",
                d.a_worst.x(), d.a_worst.y(), d.a_worst.z(), d.b_worst.x(), d.b_worst.y(), d.b_worst.z(),
                scan2cad::nearest_point_distance_mm(cloud, d.b_worst));
    std::printf("method %s points %zu used %zu outliers_removed %zu | reconstruct %.1f s repair %.1f s total %.1f s | "
                "hausdorff %.3f mm (out->ref %.3f, ref->out %.3f) p95 %.3f mm mean %.3f mm | closed %d manifold %d "
                "self-intersecting %d faces %zu holes_filled_in_repair %zu\n",
                scan2cad::reconstruct_method_name(opt.method).c_str(), cloud.points.size(), rs.points_used,
                rs.outliers_removed, t_rec, t_rep, t_rec + t_rep, d.hausdorff_mm, d.a_to_b_max_mm, d.b_to_a_max_mm,
                d.p95_mm, d.mean_mm, rr.closed, rr.manifold, rr.self_intersecting_after, rr.output_faces,
                rr.holes.size());
    return 0;
  });
}
