// assemble — places the respirator on the head and writes one solver model and its two decks.
//
// Inputs:  --head head layers.msh, --respirator respirator layers.msh, --straps straps.msh,
//          --landmarks landmarks.json, --materials data/materials.json
// Outputs: --out model.msh (every part × layer, head_skin, respirator_inner, strap ends,
//          attach_* points, bone / back_of_head), --deck1 stage1.json, --deck2 stage2.json
//          (solve/README.md format; stage 2 starts from <deck2 dir>/stage1/state.bin unless --state1)
// Sample run:
//   assemble --head head/layers.msh --respirator respirator/layers.msh --straps straps.msh
//     --landmarks head/landmarks.json --materials data/materials.json --out model.msh
//     --deck1 stage1.json --deck2 stage2.json
#include <cstdio>
#include <nlohmann/json.hpp>

#include "meshing/assemble.h"
#include "pipeline/atomic_write.h"
#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/progress.h"
#include "pipeline/read_json.h"
#include "pipeline/units.h"

int main(int argc, char** argv) {
  std::string head, resp, straps, landmarks, materials, out, deck1, deck2, state1 = "stage1/state.bin";
  meshing::PlaceOptions opt;
  double strap_t = 1.0;
  pipeline::Cli cli("assemble", "Positions the respirator (3 mm gap) and writes the solver model and decks.");
  cli.option("-H", "--head", &head, "head layers (.msh)", pipeline::required)
      .option("-r", "--respirator", &resp, "respirator layers (.msh)", pipeline::required)
      .option("-s", "--straps", &straps, "straps (.msh)", pipeline::required)
      .option("-l", "--landmarks", &landmarks, "landmarks JSON", pipeline::required)
      .option("-m", "--materials", &materials, "data/materials.json", pipeline::required)
      .option("-o", "--out", &out, "output model (.msh)", pipeline::required)
      .option("-1", "--deck1", &deck1, "output stage I deck (.json)", pipeline::required)
      .option("-2", "--deck2", &deck2, "output stage II deck (.json)", pipeline::required)
      .option("-S", "--state1", &state1, "stage I state file named in the stage II deck, relative to that deck's folder")
      .option("-g", "--gap-mm", &opt.gap_mm, "minimum respirator-skin gap [mm]", 0.1, 20)
      .option("-b", "--bridge-offset-mm", &opt.bridge_offset_mm, "rim top below the sellion [mm]", -30, 60)
      .option("-R", "--max-rim-off-mm", &opt.max_rim_off_mm,
              "refuse a respirator whose rim stands farther off the skin once placed [mm, median over its rim]", 0.1, 1000)
      .option("-t", "--strap-thickness-mm", &strap_t, "strap shell thickness [mm]", 0.1, 5);
  return pipeline::run_main(cli, argc, argv, [&] {
    pipeline::require_distinct_files({{"--head", head}, {"--respirator", resp}, {"--straps", straps}, {"--landmarks", landmarks},
                                      {"--materials", materials}, {"--out", out}, {"--deck1", deck1}, {"--deck2", deck2}});
    // 1. Load.
    pipeline::require_extension("--out", out, {".msh"});
    pipeline::require_extension("--deck1", deck1, {".json"});
    pipeline::require_extension("--deck2", deck2, {".json"});
    // solve writes its state as state.bin; '' or a deck's name went into deck2 with exit 0
    pipeline::require_extension("--state1", state1, {".bin"});
    pipeline::require_writable_outputs({out, deck1, deck2});
    const auto h = layering::read_fe_model(head);
    meshing::require_layered(h, head, "head");
    pipeline::require_mm(head, pipeline::largest_extent(h.nodes), "head");
    const auto r = layering::read_fe_model(resp);
    meshing::require_layered(r, resp, "respirator");
    pipeline::require_mm(resp, pipeline::largest_extent(r.nodes), "respirator");
    const auto s = layering::read_fe_model(straps);
    meshing::require_straps(s, straps);
    pipeline::require_mm(straps, pipeline::largest_extent(s.nodes), "head", "head's strap set");
    const auto lm = meshing::read_landmarks(landmarks);
    const auto mat = pipeline::read_json(materials);
    pipeline::naming_file(materials, [&] {  // checked before the placement's work
      meshing::deck_materials(mat);
      meshing::contact_penalty_scale(mat);
      return meshing::stage1_damping_alpha(mat);
    });
    meshing::require_landmarks_near_skin(h, lm, landmarks);
    // 2. Place and merge (checks the gap and that nothing intersects).
    meshing::AssembleReport rep;
    const auto model = meshing::assemble_model(h, r, s, lm, opt, &rep);
    meshing::require_straps_clear_for_thickness(rep.strap_gap_mm, strap_t, straps);
    // 3. Write model and decks.
    const auto d1 = pipeline::naming_file(materials, [&] { return meshing::make_deck(model, mat, 1, strap_t, ""); });
    const auto d2 = pipeline::naming_file(materials, [&] { return meshing::make_deck(model, mat, 2, strap_t, state1); });
    pipeline::write_all_or_none({{out, [&] { layering::write_fe_model(model, out); }},
                                 {deck1, [&] { pipeline::write_text_atomic(deck1, d1.dump(2) + "\n"); }},
                                 {deck2, [&] { pipeline::write_text_atomic(deck2, d2.dump(2) + "\n"); }}});
    char line[600];
    std::snprintf(line, sizeof line,
                  "%s: %zu nodes, %zu wedges, %zu strap quads; respirator shifted by (%.1f, %.1f, %.1f) mm; gap %.3f mm; "
                  "rim %.1f mm off the skin (median; largest %.1f mm); "
                  "straps %.2f mm off the skin, attached within %.2f mm of the rim; %zu intersecting face pairs",
                  out.c_str(), rep.nodes, rep.wedges, rep.quads, rep.shift.x(), rep.shift.y(), rep.shift.z(), rep.gap_mm,
                  rep.rim_median_mm, rep.rim_max_mm,
                  rep.strap_gap_mm, rep.attach_offset_mm, rep.intersecting_pairs);
    pipeline::log("assemble", line);
    return 0;
  });
}
