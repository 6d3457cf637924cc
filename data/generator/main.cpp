/// generate_scan: makes a scanner-like point cloud (binary PLY, no normals) of a generated
/// headform or N95 respirator, or of any given mesh.
///
/// Inputs:  --kind head|respirator --id ID --params JSON  (a generated model), or
///          --from-mesh MESH                             (scan a given surface)
/// Outputs: --out cloud.ply; optionally --clean-mesh surface.ply (the clean reference surface)
///          and --holes-out holes.json (centre, normal, radius of every hole made).
/// Sample runs:
///   generate_scan --kind head --id medium --params data/generator/headforms.json --out head.ply
///   generate_scan --from-mesh NIOSH_medium_20k.stl --points 200000 --noise-mm 0.3
///       --outlier-fraction 0.01 --holes 3 --hole-diameter-mm 10:20 --seed 1 --out cloud.ply
#include <string>

#include "data/generator/generate_scan.h"
#include "pipeline/atomic_write.h"
#include "pipeline/cli.h"
#include "pipeline/progress.h"
#include "pipeline/write_mesh.h"

int main(int argc, char** argv) {
  generator::GenerateRequest rq;
  std::string out, clean_mesh, holes_out, holes_diam = "10:20", noise_dir = "normal";
  std::uint64_t seed = 1;
  pipeline::Cli cli("generate_scan",
                    "Simulates a structured-light scan (noise, holes, outliers, spikes) of a generated "
                    "headform or respirator (--kind, --id and --params), or of a given mesh (--from-mesh).");
  cli.option("-k", "--kind", &rq.kind, "generated model: head or respirator; with --from-mesh, what the mesh is (its size guesses its unit; default head)")
      .option("-d", "--id", &rq.id, "model id in the params file (e.g. medium, onesize)")
      .option("-p", "--params", &rq.params_path, "params JSON (data/generator/headforms.json, respirators.json)")
      .option("-m", "--from-mesh", &rq.mesh_path, "scan this mesh instead (PLY/STL/OBJ/OFF)")
      .option("-u", "--unit", &rq.unit, "the --from-mesh mesh's length unit: auto (mm, cm or m by its size), mm, cm, m or in")
      .option("-o", "--out", &out, "output point cloud (.ply binary or .xyz)", pipeline::required)
      .option("-c", "--clean-mesh", &clean_mesh, "also write the clean reference surface (.ply/.off/.obj/.stl)")
      .option("-H", "--holes-out", &holes_out, "also write the holes made (JSON)")
      .option("-n", "--points", &rq.points, "surface samples before holes/outliers (0: from --spacing-mm)", 0, 50000000)
      .option("-s", "--spacing-mm", &rq.spacing_mm, "mean point spacing when --points is 0 [mm]", 0.1,
              generator::max_scan_spacing_mm)
      .option("-N", "--noise-mm", &rq.noise_mm, "Gaussian noise sigma [mm]", 0.0, 10.0)
      .option("-D", "--noise-direction", &noise_dir, "noise along the 'normal' or 'isotropic'")
      .option("-f", "--outlier-fraction", &rq.outlier_fraction, "share of outliers and spikes in the output", 0.0, 0.49)
      .option("-r", "--holes", &rq.random_holes, "random holes besides the model's own (-1: 0 for a mesh, 1 for a model)", -1, 1000)
      .option("-R", "--hole-diameter-mm", &holes_diam, "random hole diameter range MIN:MAX [mm], at most 100")
      .flag("-0", "--no-model-holes", &rq.no_model_holes, "generated models: no holes under the chin / in the ears")
      .option("-S", "--seed", &seed, "random seed, a whole number (same seed, same bytes)");
  return pipeline::run_main(cli, argc, argv, [&] {
    pipeline::require_distinct_files({{"--params", rq.params_path}, {"--from-mesh", rq.mesh_path}, {"--out", out},
                                      {"--clean-mesh", clean_mesh}, {"--holes-out", holes_out}});
    // 1. Resolve options.
    pipeline::require_extension("--out", out, pipeline::point_cloud_extensions);
    if (!clean_mesh.empty()) pipeline::require_extension("--clean-mesh", clean_mesh, pipeline::surface_mesh_extensions);
    if (!holes_out.empty()) pipeline::require_extension("--holes-out", holes_out, {".json"});  // it writes JSON
    rq.seed = seed;
    generator::parse_hole_diameters(holes_diam, &rq.hole_diameter_min_mm, &rq.hole_diameter_max_mm);
    rq.noise_direction = generator::parse_noise_direction(noise_dir);
    pipeline::require_writable_outputs({out, clean_mesh, holes_out});
    // 2. Build the surface and scan it.
    const generator::GeneratedScan scan = generator::generate_scan(rq);
    for (const std::string& note : {scan.unit_note, scan.rim_note})
      if (!note.empty()) pipeline::log("generate_scan", note);
    // 3. Write outputs atomically, all or none.
    pipeline::write_all_or_none({{out, [&] { pipeline::write_point_cloud(out, scan.cloud); }},
                                 {clean_mesh, [&] { pipeline::write_surface_mesh(clean_mesh, scan.clean_mesh); }},
                                 {holes_out, [&] { generator::write_holes_json(holes_out, scan.holes); }}});
    pipeline::log("generate_scan", std::to_string(scan.cloud.points.size()) + " points, " +
                                       std::to_string(scan.holes.size()) + (scan.holes.size() == 1 ? " hole -> " : " holes -> ") + out);
    return 0;
  });
}
