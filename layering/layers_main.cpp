// layers — offsets the face parts of a labelled surface mesh into 6-node wedge (pentahedron)
// layers with the tissue stacks of data/materials.json; or the respirator's inner face into its
// seal and outer layers.
//
// Inputs:  --in surface.msh (gmsh, triangles in physical groups forehead, left_cheek, right_cheek,
//          chin, back_of_head; or respirator_inner), --materials data/materials.json
// Outputs: --out layers.msh (msh 4.1: one physical group per part × tissue, surfaces head_skin,
//          <part>_skin_surface, <part>_bone_inner, back_of_head; respirator: respirator_seal,
//          respirator_outer, respirator_inner, respirator_rim); optional --report JSON.
// Sample runs:
//   layers --in build/cases/medium_onesize/head/surface.msh --materials data/materials.json --out layers.msh
//   layers --in respirator/surface.msh --materials data/materials.json --kind respirator --out resp.msh
#include <cstdio>
#include <nlohmann/json.hpp>

#include "layering/layers.h"
#include "pipeline/atomic_write.h"
#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/progress.h"
#include "pipeline/units.h"

int main(int argc, char** argv) {
  std::string in, materials, out, kind = "head", per_tissue, report_path;
  layering::LayerOptions opt;
  pipeline::Cli cli("layers", "Offsets face parts (or the respirator inner face) into wedge layers.");
  cli.option("-i", "--in", &in, "labelled surface mesh (.msh)", pipeline::required)
      .option("-m", "--materials", &materials, "materials and layer stacks (data/materials.json)", pipeline::required)
      .option("-o", "--out", &out, "output layered model (.msh)", pipeline::required)
      .option("-k", "--kind", &kind, "head or respirator")
      .option("-n", "--elements-per-layer", &opt.elements_per_layer, "element layers through each tissue", 1, 20)
      .option("-t", "--elements-per-tissue", &per_tissue, "per-material override, e.g. fat=3,skin=2")
      .option("-s", "--smoothing-mm", &opt.smoothing_mm, "reach of the smoothing of the offset directions [mm]", 0.0, 100.0)
      .option("-j", "--min-jacobian", &opt.min_scaled_jacobian, "minimum scaled Jacobian of every wedge", 0.01, 0.9)
      .option("-r", "--report", &report_path, "optional JSON report (counts, quality, volumes)");
  return pipeline::run_main(cli, argc, argv, [&] {
    pipeline::require_distinct_files({{"--in", in}, {"--materials", materials}, {"--out", out}, {"--report", report_path}});
    // 1. Options (run_main has logged them).
    pipeline::require_extension("--out", out, {".msh"});
    if (!report_path.empty()) pipeline::require_extension("--report", report_path, {".json"});
    opt.kind = kind;
    pipeline::require_writable_outputs({out, report_path});
    // 2. Load surface and stacks.
    const auto stacks = layering::read_stacks(materials, kind);
    opt.elements_per_tissue = layering::parse_elements_per_tissue(per_tissue, stacks);
    const layering::FeModel surface = layering::read_fe_model(in);
    pipeline::require_mm(in, pipeline::largest_extent(surface.nodes), kind);
    layering::require_stack_for_every_part(surface, stacks, in, materials);
    layering::require_clean_triangles(surface, in);
    layering::require_one_oriented_sheet(surface, in);
    layering::require_cheeks_on_their_sides(surface, in);
    // 3. Layers.
    layering::LayerReport rep;
    const layering::FeModel model =
        pipeline::naming_file(in, [&] { return layering::build_layers(surface, stacks, opt, &rep); });
    // 4. The model and the report, both or neither.
    nlohmann::json j = {{"wedges", rep.wedges}, {"shell_triangles", rep.shell_triangles}, {"nodes", rep.nodes},
                        {"min_scaled_jacobian", rep.min_scaled_jacobian}, {"min_volume_mm3", rep.min_volume},
                        {"reduced_columns", rep.reduced_columns}, {"min_depth_scale", rep.min_depth_scale},
                        {"intersecting_face_pairs", rep.intersecting_pairs}};
    for (const auto& v : rep.volumes)
      j["volumes"].push_back({{"group", v.group}, {"wedges", v.wedges}, {"thickness_mm", v.thickness},
                              {"volume_mm3", v.volume}, {"skin_area_x_thickness_mm3", v.skin_area_volume},
                              {"mid_area_x_thickness_mm3", v.mid_area_volume},
                              {"full_depth_volume_mm3", v.full_depth_volume},
                              {"full_depth_mid_area_x_thickness_mm3", v.full_depth_mid_area_volume},
                              {"full_depth_area_fraction", v.full_depth_area_fraction}});
    pipeline::write_all_or_none({{out, [&] { layering::write_fe_model(model, out); }},
                                 {report_path, [&] { pipeline::write_text_atomic(report_path, j.dump(2) + "\n"); }}});
    // 5. The summary, once both files are written (a failed write prints only its error).
    char line[320];
    std::snprintf(line, sizeof line, "%s: %zu wedges, %zu shell triangles, %zu nodes, min scaled Jacobian %.3f",
                  out.c_str(), rep.wedges, rep.shell_triangles, rep.nodes, rep.min_scaled_jacobian);
    pipeline::log("layers", line);
    for (const auto& v : rep.volumes) {
      std::snprintf(line, sizeof line,
                    "  %-22s %6zu wedges  volume %9.0f mm3  vs mid-area x t %+6.1f %%  vs skin-area x t %+6.1f %%"
                    "  full-depth part (%3.0f %% of area) vs mid-area x t %+6.1f %%",
                    v.group.c_str(), v.wedges, v.volume, 100 * (v.volume / v.mid_area_volume - 1),
                    100 * (v.volume / v.skin_area_volume - 1), 100 * v.full_depth_area_fraction,
                    100 * (v.full_depth_volume / std::max(v.full_depth_mid_area_volume, 1e-300) - 1));
      pipeline::log("layers", line);
    }
    for (const std::string& w : layering::volume_shortfall_warnings(rep)) pipeline::log("layers", "warning: " + w);
    return 0;
  });
}
