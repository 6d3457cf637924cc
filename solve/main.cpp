// solve — compact explicit finite-element contact solver (DESIGN.md, physics; solve/README.md).
//
// Inputs:  --model model.msh (gmsh, named physical groups), --deck deck.json (solve/README.md)
// Outputs: in --out-dir: results.msh, state.bin, energy.csv, forces.csv; on divergence only
//          diverged_state.bin and diverged_energy.csv (exit code 3).
//
// Sample runs:
//   solve --model block.msh --deck block.json --out-dir out/
//   solve --model model.msh --deck stage1.json --out-dir stage1/ --end-time-ms 20   # a 20 ms trial
//   solve --model model.msh --deck stage2.json --out-dir stage2/   # starts from its initial_state
//   solve --model model.msh --deck longer.json --out-dir stage2/ --restart stage2/state.bin  # continues
#include <string>

#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/progress.h"
#include "solve/load_model.h"
#include "solve/run.h"

int main(int argc, char** argv) {
  std::string msh, deck;
  double end_time_ms = 0;
  solve::RunOptions opt;
  pipeline::Cli cli("solve", "Explicit dynamic FE run of a gmsh model driven by a JSON deck (see solve/README.md).");
  cli.option("-m", "--model", &msh, "model mesh (.msh with named physical groups)", pipeline::required)
      .option("-d", "--deck", &deck, "deck (.json)", pipeline::required)
      .option("-o", "--out-dir", &opt.out_dir, "output directory", pipeline::required)
      .option("-r", "--restart", &opt.restart,
              "continue a run from its state.bin, in its own time, to a later end time (overrides the deck's "
              "initial_state; stage II starts from stage I through its deck's initial_state, without this)")
      .option("-e", "--end-time-ms", &end_time_ms,
              "stop at this time [ms] instead of the deck's control.end_time: a shorter trial (0: the deck's)", 0, 1e9)
      .option("-t", "--threads", &opt.threads, "OpenMP threads (0: default)", 0, 256);
  return pipeline::run_main(cli, argc, argv, [&] {
    // 1. Load and check the model.
    solve::Model model = solve::load_model(msh, deck);
    if (end_time_ms > 0) model.control.end_time = end_time_ms;
    solve::require_inputs_apart_from_outputs(opt.out_dir, msh, deck, solve::starting_state_file(model, opt),
                                             !opt.restart.empty());
    // 2. Run; outputs are written atomically by run().
    const solve::RunSummary s = solve::run(model, opt);
    using pipeline::format_number;
    pipeline::log("solve", "done: t = " + format_number(s.time) + " ms, " + std::to_string(s.steps) + " steps, dt " +
                               format_number(s.dt) + " ms, " + format_number(s.wall_s) + " s; kinetic " +
                               format_number(s.energies.kinetic) + " mJ, internal " +
                               format_number(s.energies.internal) + " mJ; largest penetration " +
                               format_number(s.max_penetration) + " mm; outputs in " + opt.out_dir);
    return 0;
  });
}
