// solve — compact explicit finite-element contact solver (DESIGN.md, physics; solve/README.md).
//
// Inputs:  --model model.msh (gmsh, named physical groups), --deck deck.json (solve/README.md)
// Outputs: in --out-dir: results.msh, state.bin, energy.csv, forces.csv; on divergence only
//          diverged_state.bin and diverged_energy.csv (exit code 3).
//
// Sample runs:
//   solve --model block.msh --deck block.json --out-dir out/
//   solve --model case.msh --deck stage2.json --out-dir stage2/ --restart stage1/state.bin
#include <string>

#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/progress.h"
#include "solve/load_model.h"
#include "solve/run.h"

int main(int argc, char** argv) {
  std::string msh, deck;
  solve::RunOptions opt;
  pipeline::Cli cli("solve", "Explicit dynamic FE run of a gmsh model driven by a JSON deck (see solve/README.md).");
  cli.option("-m", "--model", &msh, "model mesh (.msh with named physical groups)", pipeline::required)
      .option("-d", "--deck", &deck, "deck (.json)", pipeline::required)
      .option("-o", "--out-dir", &opt.out_dir, "output directory", pipeline::required)
      .option("-r", "--restart", &opt.restart, "continue from this state.bin (overrides the deck's initial_state)")
      .option("-t", "--threads", &opt.threads, "OpenMP threads (0: default)", 0, 256);
  return pipeline::run_main(cli, argc, argv, [&] {
    // 1. Load and check the model.
    const solve::Model model = solve::load_model(msh, deck);
    solve::require_inputs_apart_from_outputs(opt.out_dir, msh, deck, solve::starting_state_file(model, opt));
    // 2. Run; outputs are written atomically by run().
    const solve::RunSummary s = solve::run(model, opt);
    using pipeline::format_number;
    pipeline::log("solve", "done: t = " + format_number(s.time) + " ms, " + std::to_string(s.steps) + " steps, dt " +
                               format_number(s.dt) + " ms, " + format_number(s.wall_s) + " s; kinetic " +
                               format_number(s.energies.kinetic) + " mJ, internal " +
                               format_number(s.energies.internal) + " mJ; outputs in " + opt.out_dir);
    return 0;
  });
}
