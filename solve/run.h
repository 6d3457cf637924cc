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

/// @throws pipeline::Error(bad_input) for a bad model / restart file, Error(algorithm) on
///         divergence, Error(io) when writing fails.
RunSummary run(const Model& m, const RunOptions& opt);

}  // namespace solve
