// bench_model: time and memory of the model-building stages (issue 4) on one case's surface meshes:
// layers of the head and of the respirator, straps, and assemble (placement, merge, intersection
// checks, decks), each through the same library calls as the stage programs, without file writing.
// Every step runs --repeat times; the minimum and mean wall times, the process CPU time and the
// peak resident memory of the whole run are printed.
//
// Sample run (after `make case=medium_onesize`):
//   build/bin/bench_model --case build/cases/medium_onesize --materials data/materials.json
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <functional>
#include <nlohmann/json.hpp>

#include "layering/layers.h"
#include "meshing/assemble.h"
#include "meshing/straps.h"
#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/read_json.h"

namespace {

// Runs `work` `repeat` times; prints min / mean wall and mean CPU seconds per run.
void time_step(const char* name, int repeat, const std::function<void()>& work) {
  using clock = std::chrono::steady_clock;
  double best = 1e300, sum = 0, cpu_sum = 0;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = clock::now();
    const std::clock_t c0 = std::clock();
    work();
    const double wall = std::chrono::duration<double>(clock::now() - t0).count();
    cpu_sum += double(std::clock() - c0) / CLOCKS_PER_SEC;
    best = std::min(best, wall);
    sum += wall;
  }
  std::printf("%-22s wall min %7.3f s  mean %7.3f s  cpu mean %7.3f s  (%d runs)\n", name, best, sum / repeat,
              cpu_sum / repeat, repeat);
}

}  // namespace

int main(int argc, char** argv) {
  std::string case_dir, materials = "data/materials.json";
  int repeat = 3;
  pipeline::Cli cli("bench_model", "Times layers (head, respirator), straps and assemble on one case's surface meshes.");
  cli.option("-c", "--case", &case_dir, "case folder with head/ and respirator/ (surface.msh, landmarks.json)",
             pipeline::required)
      .option("-m", "--materials", &materials, "materials and layer stacks (data/materials.json)")
      .option("-n", "--repeat", &repeat, "runs of each step", 1, 100);
  return pipeline::run_main(cli, argc, argv, [&] {
    const auto head_surface = layering::read_fe_model(case_dir + "/head/surface.msh");
    const auto resp_surface = layering::read_fe_model(case_dir + "/respirator/surface.msh");
    const auto lm = meshing::read_landmarks(case_dir + "/head/landmarks.json");
    const auto head_stacks = layering::read_stacks(materials, "head");
    const auto resp_stacks = layering::read_stacks(materials, "respirator");
    const auto mat = pipeline::read_json(materials);

    layering::FeModel head, resp, straps, model;
    layering::LayerReport head_rep, resp_rep;
    meshing::AssembleReport asm_rep;
    layering::LayerOptions head_opt, resp_opt;
    head_opt.kind = "head";
    resp_opt.kind = "respirator";
    std::printf("bench_model: %s\n", case_dir.c_str());
    time_step("layers (head)", repeat, [&] { head = layering::build_layers(head_surface, head_stacks, head_opt, &head_rep); });
    time_step("layers (respirator)", repeat,
              [&] { resp = layering::build_layers(resp_surface, resp_stacks, resp_opt, &resp_rep); });
    time_step("straps", repeat, [&] { straps = meshing::make_straps(head, lm, resp, meshing::StrapOptions{}, nullptr); });
    time_step("assemble + decks", repeat, [&] {
      model = meshing::assemble_model(head, resp, straps, lm, meshing::PlaceOptions{}, &asm_rep);
      const auto d1 = meshing::make_deck(model, mat, 1, 1.0, "");
      const auto d2 = meshing::make_deck(model, mat, 2, 1.0, "stage1/state.bin");
      if (d1.empty() || d2.empty()) throw pipeline::Error(pipeline::ErrorKind::algorithm, "empty deck");
    });
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    std::printf("head %zu wedges (min SJ %.3f), respirator %zu wedges, model %zu nodes / %zu wedges / %zu quads, "
                "gap %.3f mm\npeak resident memory %.1f MB\n",
                head_rep.wedges, head_rep.min_scaled_jacobian, resp_rep.wedges, asm_rep.nodes, asm_rep.wedges,
                asm_rep.quads, asm_rep.gap_mm, ru.ru_maxrss / 1024.0);
    return 0;
  });
}
