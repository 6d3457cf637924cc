// reconstruct: scanned point cloud → triangle mesh (meshes pass through, scaled to mm).
//
// Inputs:  --in SCAN (PLY/STL/OBJ/OFF/XYZ, any unit: m/cm detected and scaled to mm)
// Outputs: --out MESH (triangle mesh [mm]; .ply binary, .off, .obj or .stl)
// Sample runs:
//   reconstruct --in scan.ply --kind head --out reconstructed.ply
//   reconstruct --in shell.xyz --kind respirator --method advancing_front --out reconstructed.ply
#include "pipeline/atomic_write.h"
#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/progress.h"
#include "pipeline/read_scan.h"
#include "pipeline/write_mesh.h"
#include "scan2cad/reconstruct.h"

int main(int argc, char** argv) {
  std::string in, out, method_name = "auto";
  scan2cad::KindAndUnitOptions kind_unit;
  scan2cad::ReconstructOptions opt;
  pipeline::Cli cli("reconstruct", "Reconstructs a triangle mesh from a scanned point cloud (CGAL).");
  cli.option("-i", "--in", &in, "input scan: .ply .stl .obj .off (points or mesh), or points as text: .xyz .pts .txt .csv .asc (x y z, then normals, colours, intensity...)", pipeline::required);
  cli.option("-o", "--out", &out, "output mesh (.ply .off .obj .stl): triangles from points; a mesh given is written as read, its polygons and seams kept (repair makes them one triangle mesh)", pipeline::required);
  kind_unit.add_to(cli, "head or respirator (sets defaults and unit guess)");
  cli.option("-m", "--method", &method_name, "auto, poisson, advancing_front or scale_space");
  cli.option("-n", "--neighbors", &opt.neighbors, "neighbours for spacing, outliers, normals", 6, 200);
  cli.option("-f", "--outlier-factor", &opt.outlier_factor, "outlier if mean k-NN distance > f x spacing", 1.1, 1e6);
  cli.option("-c", "--cell", &opt.simplify_cell_mm, "grid simplification cell [mm], 0 = none", 0.0, 50.0);
  cli.option("-C", "--denoised-cell", &opt.denoised_cell_mm, "grid cell after smoothing [mm], 0 = none (faster on dense scans, loses thin ears)", 0.0, 50.0);
  cli.option("-g", "--poisson-cell", &opt.poisson_cell_mm,
             "Poisson: grid cell of its input after the normals [mm], 0 = all points (cut and projection use all)",
             0.0, 50.0);
  bool thin_parts_thinned = false;
  cli.flag("-G", "--poisson-thin-parts-thinned", &thin_parts_thinned,
           "Poisson: thin the points of thin parts to --poisson-cell like the rest (default: all of them go to Poisson)");
  cli.option("-d", "--poisson-distance", &opt.poisson_distance_mm, "Poisson contouring accuracy [mm]", 1e-3, 10.0);
  int density_points = int(opt.density_reference_points);
  cli.option("-D", "--density-reference", &density_points,
             "heads: keep a seeded random subset of this many points of a denser scan, 0 = all", 0, 2000000000);
  cli.option("-P", "--projection-max-move", &opt.projection_max_move_mm,
             "Poisson: move output vertices onto the points by at most this [mm], 0 = off", 0.0, 50.0);
  bool onto_smoothed = false;
  cli.flag("-S", "--project-onto-smoothed", &onto_smoothed,
           "Poisson: project onto the jet-smoothed points (default: onto the unsmoothed ones)");
  cli.option("-K", "--projection-neighbors", &opt.projection_neighbors,
             "Poisson: neighbours of the projection's quadric on the unsmoothed points", 6, 200);
  cli.option("-H", "--hole-cut-spacings", &opt.hole_cut_spacings,
             "Poisson: cut faces farther than this many spacings from the points (scan holes, filled by repair), 0 = off",
             0.0, 100.0);
  cli.option("-U", "--untangle-rounds", &opt.untangle_rounds,
             "Poisson: rounds of cutting out and refilling faces the projection made cross, 0 = leave them to repair", 0,
             20);
  cli.option("-w", "--orientation-crossing-weight", &opt.orientation_crossing_weight,
             "normal orientation: cost of a tree link along the normals (across a thin part), 0 = CGAL's MST", 0.0,
             100.0);
  bool no_refit = false;
  cli.flag("-R", "--no-own-side-refit", &no_refit,
           "keep the smoothing over plain neighbourhoods (default: points with the other side of a thin part in "
           "reach are smoothed again over their own side once oriented)");
  cli.option("-r", "--own-side-min-cos", &opt.refit_min_cos,
             "own-side refit: a neighbour is on a point's side when their normals' cosine exceeds this", -1.0, 1.0);
  bool keep_support = false;
  cli.flag("-B", "--keep-support", &keep_support,
           "keep the points of a table or turntable the object stood on (default: a plane at the edge of the "
           "scan that reaches beyond the object is removed)");
  cli.option("-M", "--max-spacing-mm", &opt.max_head_spacing_mm,
             "refuse a head cloud whose points are farther apart [mm, mean spacing to 6 neighbours], 0 = no check: its ears are lost",
             0.0, 100.0);
  cli.option("-T", "--cg-tolerance", &opt.poisson_solver_tolerance, "Poisson CG relative residual", 1e-14, 1e-1);
  return pipeline::run_main(cli, argc, argv, [&] {
    pipeline::require_distinct_files({{"--in", in}, {"--out", out}});
    opt.density_reference_points = std::size_t(density_points);
    opt.refit_on_own_side = !no_refit;
    opt.remove_support = !keep_support;
    opt.projection_onto_unsmoothed = !onto_smoothed;
    opt.poisson_keep_thin_parts = !thin_parts_thinned;
    // 1. Options
    pipeline::require_extension("--out", out, pipeline::surface_mesh_extensions);
    const auto kind = kind_unit.kind();
    opt.method = scan2cad::parse_reconstruct_method(method_name, kind);
    const pipeline::ScanReadOptions ropt = kind_unit.read_options();
    pipeline::require_writable_outputs({out});
    // 2. Load
    const pipeline::Scan scan = pipeline::read_scan(in, ropt);
    pipeline::log("reconstruct", in + ": " + kind_unit.describe_unit(scan));
    kind_unit.require_plausible_size(scan, in);
    // 3. Meshes pass through as they are, in mm (repair handles soups); clouds are reconstructed
    if (scan.is_mesh) {
      pipeline::write_polygon_soup(out, scan.soup);
      pipeline::log("reconstruct", in + ": is a mesh (" + std::to_string(scan.soup.polygons.size()) +
                                       " faces), passed through unchanged but for the unit → " + out);
      return 0;
    }
    if (ropt.unit == pipeline::Unit::automatic) {
      opt.min_extent_mm = pipeline::smallest_real_share_of_extent * ropt.expected_size_mm;
      opt.max_extent_mm = pipeline::largest_real_share_of_extent * ropt.expected_size_mm;
    }
    scan2cad::ReconstructStats st;
    const pipeline::SurfaceMesh mesh =
        pipeline::naming_file(in, [&] { return scan2cad::reconstruct(scan.cloud, kind, opt, &st); });
    // 4. Write
    pipeline::write_surface_mesh(out, mesh);
    pipeline::log("reconstruct", in + ": " + std::to_string(st.input_points) + " points, " +
                                     std::to_string(st.outliers_removed) + " outliers removed, spacing " +
                                     pipeline::format_number(st.spacing_mm) + " mm, " + std::to_string(st.faces) +
                                     " triangles → " + out +
                                     (st.thin_shell ? " (thin shell, wall " + pipeline::format_number(st.wall_mm) + " mm)" : ""));
    return 0;
  });
}
