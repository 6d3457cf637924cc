// straps — lays the two respirator straps (4-node quad shell bands) on the head.
//
// Inputs:  --head layers.msh (head; checked by meshing::require_layered), --landmarks landmarks.json,
//          --respirator respirator layers.msh (groups respirator_inner, respirator_rim)
// Outputs: --out straps.msh (groups strap_top, strap_bottom, strap_*_end_*, strap_*_attach_*)
// Sample run:
//   straps --head head/layers.msh --landmarks head/landmarks.json --respirator respirator/layers.msh --out straps.msh
#include <cstdio>

#include "layering/layers.h"
#include "meshing/straps.h"
#include "pipeline/atomic_write.h"
#include "pipeline/cli.h"
#include "pipeline/progress.h"
#include "pipeline/units.h"

int main(int argc, char** argv) {
  std::string head, landmarks, resp, out;
  meshing::StrapOptions opt;
  pipeline::Cli cli("straps", "Lays the top and bottom respirator straps on the head.");
  cli.option("-H", "--head", &head, "head model (.msh)", pipeline::required)
      .option("-l", "--landmarks", &landmarks, "landmarks JSON", pipeline::required)
      .option("-r", "--respirator", &resp, "respirator layers (.msh)", pipeline::required)
      .option("-o", "--out", &out, "output straps (.msh)", pipeline::required)
      .option("-L", "--length-mm", &opt.length_mm, "unstretched strap length [mm]", 50, 1000)
      .option("-w", "--width-mm", &opt.width_mm, "strap width [mm]", 1, 30)
      .option("-t", "--thickness-mm", &opt.thickness_mm,
              "strap thickness [mm]: half of it is added to the straps' clearance off the skin; the decks take "
              "assemble's --strap-thickness-mm, give both the same",
              0.1, 5)
      .option("-g", "--gap-mm", &opt.place.gap_mm, "respirator-skin gap used for the placement, as assemble's [mm]", 0.1, 20)
      .option("-b", "--bridge-offset-mm", &opt.place.bridge_offset_mm, "rim top below the sellion, as assemble's [mm]",
              -30, 60)
      .option("-R", "--max-rim-off-mm", &opt.place.max_rim_off_mm,
              "refuse a respirator whose rim stands farther off the skin once placed [mm, median over its rim], as assemble's",
              0.1, 1000)
      .option("-s", "--max-stretch-percent", &opt.max_stretch_percent,
              "refuse a strap the head's outline stretches by more than this [% of its length]", 0, 1000);
  return pipeline::run_main(cli, argc, argv, [&] {
    pipeline::require_distinct_files({{"--head", head}, {"--landmarks", landmarks}, {"--respirator", resp}, {"--out", out}});
    // 1. Load.
    pipeline::require_extension("--out", out, {".msh"});
    pipeline::require_writable_outputs({out});
    const auto h = layering::read_fe_model(head);
    meshing::require_layered(h, head, "head");
    pipeline::require_mm(head, pipeline::largest_extent(h.nodes), "head");
    const auto lm = meshing::read_landmarks(landmarks);
    meshing::require_landmarks_near_skin(h, lm, landmarks);
    const auto r = layering::read_fe_model(resp);
    meshing::require_layered(r, resp, "respirator");
    pipeline::require_mm(resp, pipeline::largest_extent(r.nodes), "respirator");
    // 2. Lay the straps.
    meshing::StrapReport rep;
    const auto straps = meshing::make_straps(h, lm, r, opt, &rep);
    // 3. Write.
    layering::write_fe_model(straps, out);
    char line[400];
    std::snprintf(line, sizeof line,
                  "%s: %zu quads, top %.1f mm (y = %.1f mm at the back; outline %.0f mm: stretched >= %.0f %%), "
                  "bottom %.1f mm (outline %.0f mm: >= %.0f %%), min distance to skin %.2f mm",
                  out.c_str(), rep.quads, rep.top_length, rep.top_back_y, rep.top_outline,
                  100 * (rep.top_outline / opt.length_mm - 1), rep.bottom_length, rep.bottom_outline,
                  100 * (rep.bottom_outline / opt.length_mm - 1), rep.min_gap);
    pipeline::log("straps", line);
    return 0;
  });
}
