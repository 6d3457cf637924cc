#include "solve/save_state.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"
#include "pipeline/require_file.h"

namespace solve {
namespace {
// v2 adds the contact history after the v1 content; v3 the contact step after the eight
// scalars. v1 and v2 files still load (no contact history; the contact step is the step).
const char kMagic[16] = "SOLVE_STATE_v3\n";
const char kMagicV2[16] = "SOLVE_STATE_v2\n";
const char kMagicV1[16] = "SOLVE_STATE_v1\n";

void put_vec(std::ofstream& o, const std::vector<double>& v) {
  const std::uint64_t n = v.size();
  o.write(reinterpret_cast<const char*>(&n), sizeof n);
  o.write(reinterpret_cast<const char*>(v.data()), std::streamsize(n * sizeof(double)));
}
}  // namespace

void save_state(const std::string& path, const SolverState& s) {
  pipeline::write_atomic(path, [&](const std::string& tmp) {
    std::ofstream o(tmp, std::ios::binary);
    o.write(kMagic, sizeof kMagic);
    const double scalars[9] = {s.time, s.dt, double(s.step), s.e_contact, s.e_damping, s.w_external, s.e_initial,
                               s.e_initial_set ? 1.0 : 0.0, s.dt_contact};
    o.write(reinterpret_cast<const char*>(scalars), sizeof scalars);
    put_vec(o, s.X);
    put_vec(o, s.x);
    put_vec(o, s.v);
    put_vec(o, s.rigid);
    const std::uint64_t n_pairs = s.contact_history.size();
    o.write(reinterpret_cast<const char*>(&n_pairs), sizeof n_pairs);
    for (const auto& h : s.contact_history) put_vec(o, h);
    o.close();  // the last buffer reaches the file here: a full disk shows now, not at the next run
    if (!o) throw pipeline::io_failed(path, "write failed: " + pipeline::why_write_failed());
  });
}

SolverState load_state(const std::string& path) {
  pipeline::require_file(path);  // a pipe given as --restart blocked the run
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw pipeline::bad_input(path, "cannot open the state file");
  const std::uint64_t file_bytes = std::uint64_t(in.tellg());
  in.seekg(0);
  char magic[16];
  in.read(magic, sizeof magic);
  const bool v1 = in && std::memcmp(magic, kMagicV1, sizeof magic) == 0;
  const bool v2 = in && std::memcmp(magic, kMagicV2, sizeof magic) == 0;
  if (!in || (!v1 && !v2 && std::memcmp(magic, kMagic, sizeof magic) != 0))
    throw pipeline::bad_input(path, "not a solve state file (bad header)");
  double sc[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  const std::size_t n_scalars = v1 || v2 ? 8 : 9;
  in.read(reinterpret_cast<char*>(sc), std::streamsize(n_scalars * sizeof(double)));
  if (!in) throw pipeline::bad_input(path, "truncated state file");
  // A damaged file is refused here, not run: a count past the file's end would allocate up to
  // 32 GB before the read failed, and a NaN position only shows as a "diverged" run (exit 3).
  auto check_finite = [&](const double* v, std::size_t n, const char* what) {
    for (std::size_t i = 0; i < n; ++i)
      if (!std::isfinite(v[i]))
        throw pipeline::bad_input(path, std::string("non-finite value in the state's ") + what + " at index " +
                                            std::to_string(i));
  };
  check_finite(sc, n_scalars, "time, step and energies");
  if (!(sc[2] >= 0 && sc[2] < 1e15)) throw pipeline::bad_input(path, "step count " + pipeline::format_number(sc[2]) + " out of range");
  SolverState s;
  s.time = sc[0]; s.dt = sc[1]; s.step = long(sc[2]);
  s.e_contact = sc[3]; s.e_damping = sc[4]; s.w_external = sc[5]; s.e_initial = sc[6]; s.e_initial_set = sc[7] != 0;
  s.dt_contact = sc[8];
  auto get_vec = [&](std::vector<double>& v, const char* what) {
    std::uint64_t n = 0;
    in.read(reinterpret_cast<char*>(&n), sizeof n);
    const std::uint64_t left = in ? file_bytes - std::uint64_t(in.tellg()) : 0;
    if (!in || n > left / sizeof(double)) throw pipeline::bad_input(path, "truncated state file");
    v.resize(n);
    in.read(reinterpret_cast<char*>(v.data()), std::streamsize(n * sizeof(double)));
    if (!in) throw pipeline::bad_input(path, "truncated state file");
    check_finite(v.data(), v.size(), what);
  };
  get_vec(s.X, "reference positions");
  get_vec(s.x, "positions");
  get_vec(s.v, "velocities");
  get_vec(s.rigid, "rigid-body state");
  if (!v1) {
    std::uint64_t n_pairs = 0;
    in.read(reinterpret_cast<char*>(&n_pairs), sizeof n_pairs);
    if (!in || n_pairs > (1ull << 20)) throw pipeline::bad_input(path, "truncated state file");
    s.contact_history.resize(n_pairs);
    for (auto& h : s.contact_history) get_vec(h, "contact history");
  }
  if (s.x.size() != s.X.size() || s.v.size() != s.X.size())
    throw pipeline::bad_input(path, "inconsistent state file (array sizes differ)");
  if (const std::uint64_t end = std::uint64_t(in.tellg()); end != file_bytes)
    throw pipeline::bad_input(path, std::to_string(file_bytes - end) + " bytes after the end of the state (two files joined?)");
  return s;
}

}  // namespace solve
