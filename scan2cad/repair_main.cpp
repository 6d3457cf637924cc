// repair: reconstructed or scanned surface → clean manifold triangle mesh + JSON report.
//
// Inputs:  --in MESH (PLY/STL/OBJ/OFF, may be a non-manifold soup; any unit)
// Outputs: --out MESH.ply (closed for heads; the respirator keeps its rim), --report JSON
// Sample runs:
//   repair --in reconstructed.ply --kind head --out repaired.ply --report repair_report.json
//   repair --in NIOSH_medium_20k.stl --kind head --edge 2 --out repaired.ply --report report.json
#include <cstdio>

#include "pipeline/atomic_write.h"
#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/progress.h"
#include "pipeline/read_scan.h"
#include "pipeline/units.h"
#include "pipeline/write_mesh.h"
#include "scan2cad/repair.h"

int main(int argc, char** argv) {
  std::string in, out, report_path;
  scan2cad::KindAndUnitOptions kind_unit;
  scan2cad::RepairOptions opt;
  pipeline::Cli cli("repair", "Repairs a scanned surface: outliers, spikes, holes, self-intersections; remeshes.");
  cli.option("-i", "--in", &in, "input mesh: .ply .stl .obj .off", pipeline::required);
  cli.option("-o", "--out", &out, "output mesh (.ply .off .obj .stl)", pipeline::required);
  cli.option("-r", "--report", &report_path, "JSON report of the changes (optional)");
  kind_unit.add_to(cli, "head (closed output) or respirator (rim kept open)");
  cli.option("-e", "--edge", &opt.target_edge_mm, "target edge length [mm], 0 = no remeshing (at most 10 million triangles)", 0.0, 50.0);
  cli.option("-n", "--remesh-iterations", &opt.remesh_iterations, "isotropic remeshing iterations", 1, 20);
  cli.option("-s", "--smooth", &opt.smoothing_iterations, "mean-curvature-flow smoothing steps", 0, 100);
  cli.option("-t", "--smooth-time", &opt.smoothing_time, "smoothing time step (CGAL smooth_shape)", 1e-9, 1.0);
  cli.option("-p", "--spike-factor", &opt.spike_factor, "spike: offset from one-ring plane > p x the ring's mean radius", 0.1, 100.0);
  bool no_symmetry = false;
  cli.flag("-S", "--no-symmetric-completion", &no_symmetry,
           "heads: keep the faired hole fills (default: reshape them after the mirrored other side)");
  cli.option("-a", "--max-ring-asymmetry", &opt.symmetry.max_ring_asymmetry_mm,
             "complete a hole by symmetry only if its ring is this symmetric (RMS) [mm]", 0.0, 100.0);
  bool keep_support = false;
  cli.flag("-B", "--keep-support", &keep_support,
           "keep the faces on a table or turntable the object stood on (default: removed, as reconstruct "
           "removes its points)");
  return pipeline::run_main(cli, argc, argv, [&] {
    pipeline::require_distinct_files({{"--in", in}, {"--out", out}, {"--report", report_path}});
    // 1. Options
    pipeline::require_extension("--out", out, pipeline::surface_mesh_extensions);
    if (!report_path.empty()) pipeline::require_extension("--report", report_path, {".json"});
    opt.symmetric_completion = !no_symmetry;
    opt.remove_support = !keep_support;
    const auto kind = kind_unit.kind();
    const pipeline::ScanReadOptions ropt = kind_unit.read_options();
    if (ropt.unit == pipeline::Unit::automatic)
      opt.max_extent_mm = pipeline::largest_real_share_of_extent * ropt.expected_size_mm;
    pipeline::require_writable_outputs({out, report_path});
    // 2. Load
    const pipeline::Scan scan = pipeline::read_scan(in, ropt);
    pipeline::log("repair", in + ": " + kind_unit.describe_unit(scan));
    kind_unit.require_plausible_size(scan, in);
    if (!scan.is_mesh)
      throw pipeline::bad_input(in, "is a point cloud without faces, expected a mesh (run reconstruct first)");
    // 3. Repair
    scan2cad::RepairReport report;
    const pipeline::SurfaceMesh mesh =
        pipeline::naming_file(in, [&] { return scan2cad::repair(scan.soup, kind, opt, &report); });
    // 4. Write (both or neither)
    pipeline::write_all_or_none({{out, [&] { pipeline::write_surface_mesh(out, mesh); }},
                                 {report_path, [&] { pipeline::write_text_atomic(report_path, report.to_json().dump(2) + "\n"); }}});
    std::fprintf(stderr, "repair: %s\n", report.summary().c_str());
    if (const std::string w = report.large_fill_warning(); !w.empty())
      std::fprintf(stderr, "repair: warning: %s: %s\n", in.c_str(), w.c_str());
    return 0;
  });
}
