#pragma once
/// A complete run with outputs and the stability guard: what the `solve` program does.
///
/// Writes into out_dir (atomically, only on success): results.msh (mesh + nodal data at output
/// times), state.bin (restart), energy.csv, forces.csv (see solve/README.md). On divergence (NaN,
/// inverted element, energy balance error beyond control.energy_tolerance, penetration beyond
/// control.penetration_tolerance) it writes diverged_state.bin (last healthy state at a history
/// time) and diverged_energy.csv, never results.msh, and throws pipeline::Error(algorithm) with
/// one line saying what, when (time, step) and where the diagnostic files are.
#include <array>
#include <string>

#include "solve/model.h"
#include "solve/solver.h"

namespace solve {

struct RunOptions {
  std::string out_dir;        ///< created if missing; required
  std::string restart;        ///< state file to continue from ("" = deck's initial_state, if any)
  int threads = 0;            ///< OpenMP threads, 0 = default
  bool progress = true;       ///< progress lines on stderr
  bool write_results = true;  ///< false: only state.bin and the CSVs (tests)
};

struct RunSummary {
  double time = 0, dt = 0, stable_dt = 0, added_mass = 0, total_mass = 0, wall_s = 0;
  long steps = 0;
  Energies energies;          ///< at the last history row
  double max_penetration = 0; ///< over the run [mm]
};

/// The state file a run starts from: `opt.restart` (--restart) wins over the deck's initial_state;
/// "" = the mesh at rest.
std::string starting_state_file(const Model& m, const RunOptions& opt);

/// The files run() writes in out_dir: those of a sound run, and those of a diverged one.
inline constexpr std::array<const char*, 4> sound_run_files = {"results.msh", "state.bin", "energy.csv", "forces.csv"};
inline constexpr std::array<const char*, 2> diverged_run_files = {"diverged_state.bin", "diverged_energy.csv"};

/// @throws pipeline::Error(bad_input) for a bad model / restart file, Error(algorithm) on
///         divergence, Error(io) when writing fails.
RunSummary run(const Model& m, const RunOptions& opt);

/// Checks, before any work, that no input is a file run() writes or removes in `out_dir`: a
/// model copied into the output folder as results.msh was deleted by a diverging run and
/// overwritten by a sound one. The state a run starts from (`started_from`: --restart, else the
/// deck's initial_state) may be out_dir's state.bin when the run continues in place (--restart,
/// `continues_in_place`; run() keeps it when it fails); it may not be another output, and a new
/// stage started from the deck's initial_state may not write into the folder of that state.
/// @throws pipeline::Error(usage) "--model 'out/results.msh' is the same file as the output
///         out/results.msh: ..." (pipeline::require_distinct_files).
void require_inputs_apart_from_outputs(const std::string& out_dir, const std::string& model_path,
                                       const std::string& deck_path, const std::string& started_from,
                                       bool continues_in_place);

}  // namespace solve
