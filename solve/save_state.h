#pragma once
/// The restart / state file (`state.bin`): what a later run (Stage II after Stage I, or a
/// restarted run) starts from — reference and current positions, half-step velocities, rigid-body
/// velocities, time, step, time step and the step the contact stiffness is set with, the energy
/// accumulators and the contact history of each pair (friction stick forces, sides, search
/// state). Format v3; v2 files load without the contact step, v1 also without the history.
/// Binary, exact doubles, so a restarted run continues bit-identically to one that never stopped.
#include <string>

#include "solve/solver.h"

namespace solve {

/// Writes s to path atomically (pipeline::write_atomic). @throws pipeline::Error(io).
void save_state(const std::string& path, const SolverState& s);

/// Reads a state file. @throws pipeline::Error(bad_input) naming the file if it is missing,
/// truncated, not a state file, holds a NaN or infinite value, or has bytes after its end.
SolverState load_state(const std::string& path);

}  // namespace solve
