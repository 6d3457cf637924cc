#include "solve/run.h"

#include <fcntl.h>
#include <omp.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/atomic_write.h"
#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/progress.h"
#include "solve/save_state.h"
#include "solve/write_results.h"

namespace solve {
namespace {

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

// The first time t0 + k·interval after t. Computed, not stepped to: an interval far below the time
// step (output_interval 1e-12 ms) made the loop that added it run ~1e9 times a step.
double next_time(double t0, double interval, double t) {
  return t0 + interval * (std::floor((t + 1e-12 - t0) / interval) + 1);
}

std::string energy_row(const Energies& e) {
  return fmt(e.time) + "," + fmt(e.kinetic) + "," + fmt(e.internal) + "," + fmt(e.contact) + "," + fmt(e.damping) +
         "," + fmt(e.external) + "," + fmt(e.scheme) + "," + fmt(e.balance) + "\n";
}

void write_frame(std::ostream& out, const Model& m, const Solver& s, int index) {
  const double t = s.time();
  for (const auto& f : m.output.node_data) {
    const int n = node_data_components(f);
    if (f == "displacement") append_node_data(out, m, f, t, index, s.displacement(), n);
    if (f == "velocity") append_node_data(out, m, f, t, index, s.v(), n);
    if (f == "contact_pressure") append_node_data(out, m, f, t, index, s.contact_pressure(), n);
    if (f == "contact_shear") append_node_data(out, m, f, t, index, s.contact_shear(), n);
    if (f == "von_mises") append_node_data(out, m, f, t, index, s.von_mises(), n);
  }
}

// "232 kB", "227 TB": three digits in the largest unit under the amount.
std::string bytes_text(double bytes) {
  const char* units[] = {"bytes", "kB", "MB", "GB", "TB", "PB"};
  int u = 0;
  while (u < 5 && bytes >= 999.5) bytes /= 1000, ++u;  // 999.7 kB would print as "1e+03 kB"
  char b[32];
  std::snprintf(b, sizeof b, "%.3g %s", bytes, units[u]);
  return b;
}

// One run per output folder, for the run's life: two runs into one --out-dir shared the frames
// file and each removed the other's outputs (a finished run's results.msh deleted by the other,
// which then failed with a file system error; sweep P). The second run is refused, not queued: it
// would overwrite the first's results anyway. The lock file goes with the run, so a folder ends
// as the run leaves it; a path that no longer names the locked file (removed by the run that held
// it) is locked again.
class OutDirLock {
 public:
  explicit OutDirLock(const std::filesystem::path& dir) : path_((dir / ".solve.lock").string()) {
    for (int attempt = 0; attempt < 3; ++attempt) {
      fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
      if (fd_ < 0) throw pipeline::io_failed(path_, std::string("cannot create the run's lock file: ") + std::strerror(errno));
      if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
        ::close(fd_);
        throw pipeline::bad_input(dir.string(), "another solve is writing its outputs in this folder now: give this run "
                                                "another --out-dir, or wait for that one to end");
      }
      struct stat held {}, named {};
      if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
          held.st_dev == named.st_dev)
        return;
      ::close(fd_);
    }
    throw pipeline::io_failed(path_, "the run's lock file keeps being removed");
  }
  ~OutDirLock() {
    ::unlink(path_.c_str());
    ::close(fd_);
  }
  OutDirLock(const OutDirLock&) = delete;
  OutDirLock& operator=(const OutDirLock&) = delete;

 private:
  std::string path_;
  int fd_ = -1;
};

// A frame at every step (control.output_interval below dt) of a large model, or a history row at
// every step of a long run, can need terabytes, which a full disk would show only hours into the
// run. The need is estimated from the starting step (it can shrink as elements deform) with every
// value at its longest and the frames counted twice (they are kept in a temporary file and
// copied into results.msh), plus the mesh and the state (~100 bytes per node and per element).
// Checked on the file system out_dir will be on, before it is made.
void require_room_for_outputs(const Model& m, std::size_t elements, const std::string& out_dir, double frames,
                              double rows, bool write_results) {
  const double frame_bytes = write_results ? node_data_bytes_max(m) : 0;
  const double row_bytes = 18.0 * double(9 + 3 * m.contacts.size() + 6 * m.output.history_groups.size());
  const double need = 2 * frames * frame_bytes + rows * row_bytes + 100 * double(m.n_nodes() + elements);
  std::error_code ec;
  const std::filesystem::space_info space = std::filesystem::space(pipeline::nearest_existing_folder(out_dir), ec);
  if (ec || space.capacity == 0 || need <= double(space.available)) return;  // capacity 0: a file system that does not say
  const std::string frames_text = write_results ? fmt(frames) + " frames of " + bytes_text(frame_bytes) + ", " : "";
  throw pipeline::io_failed(out_dir, "the outputs need about " + bytes_text(need) + " (" + frames_text + fmt(rows) +
                                         " history rows), and " + bytes_text(double(space.available)) +
                                         " are free there: raise control.output_interval or history_interval");
}

// SIGINT (Ctrl-C), SIGTERM, SIGHUP (the terminal or the SSH session closed) or SIGPIPE (stderr
// piped into a program that quit, `solve ... 2>&1 | head`), noted by the handler StopSignals
// installs for the time loop. Their default action killed a run with its frames' temporary file
// left beside an earlier run's results, which looked like this run's; the loop now stops after
// its step and cleans up. A signal the run was started ignoring (SIGINT for `solve ... &` in a
// script, SIGHUP under nohup) stays ignored.
volatile std::sig_atomic_t stop_signal = 0;
extern "C" void note_stop_signal(int sig) { stop_signal = sig; }

std::string signal_name(int sig) {
  switch (sig) {
    case SIGINT: return "SIGINT (Ctrl-C)";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP (the terminal closed)";
    case SIGPIPE: return "SIGPIPE (the program reading its output quit)";
    default: return "signal " + std::to_string(sig);
  }
}

struct StopSignals {
  static constexpr int kSignals[4] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};
  struct sigaction old[4] {};
  StopSignals() {
    stop_signal = 0;
    struct sigaction a {};
    a.sa_handler = note_stop_signal;
    sigemptyset(&a.sa_mask);
    for (int k = 0; k < 4; ++k) {
      sigaction(kSignals[k], nullptr, &old[k]);
      if (old[k].sa_handler != SIG_IGN) sigaction(kSignals[k], &a, nullptr);
    }
  }
  ~StopSignals() {
    for (int k = 0; k < 4; ++k) sigaction(kSignals[k], &old[k], nullptr);
  }
};

}  // namespace

std::string starting_state_file(const Model& m, const RunOptions& opt) {
  return !opt.restart.empty() ? opt.restart : m.initial_state.file;
}

void require_inputs_apart_from_outputs(const std::string& out_dir, const std::string& model_path,
                                       const std::string& deck_path, const std::string& started_from,
                                       bool continues_in_place) {
  std::vector<std::string> outputs;
  for (const char* f : sound_run_files) outputs.push_back((std::filesystem::path(out_dir) / f).string());
  for (const char* f : diverged_run_files) outputs.push_back((std::filesystem::path(out_dir) / f).string());
  auto check = [&](const std::string& flag, const std::string& path, bool may_be_state) {
    for (const std::string& output : outputs)
      if (!(may_be_state && std::filesystem::path(output).filename() == "state.bin"))
        pipeline::require_distinct_files({{"the output " + output, output}, {flag, path}});
  };
  check("--model", model_path, false);
  check("--deck", deck_path, false);
  check("the starting state", started_from, true);
  // A new stage started from the deck's initial_state in the folder that holds that state (stage
  // II with --out-dir stage1) deleted the earlier stage's results as it started and replaced its
  // state.bin at the end, exit 0; the next stage II run then began from stage II's own state.
  const std::string state_out = (std::filesystem::path(out_dir) / "state.bin").string();
  std::error_code ec;
  if (!continues_in_place && !started_from.empty() && std::filesystem::equivalent(state_out, started_from, ec))
    throw pipeline::Error(pipeline::ErrorKind::usage,
                          "--out-dir " + out_dir + " holds " + state_out + ", the state this deck's initial_state starts "
                          "from: a run there would delete that stage's results and replace its state; give this stage "
                          "a folder of its own (--restart continues a run in place)");
}

RunSummary run(const Model& model, const RunOptions& opt) {
  constexpr double many_steps = 1e6;
  namespace fs = std::filesystem;
  if (opt.out_dir.empty()) throw pipeline::Error(pipeline::ErrorKind::usage, "no output directory given");
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  // 1. Initial state: command line restart wins over the deck's initial_state. Read before the
  // solver is set up, whose ties are matched where the run starts.
  const std::string start_file = starting_state_file(model, opt);
  // Stage II before stage I said only "stage1/state.bin: no such file".
  if (opt.restart.empty() && !start_file.empty() && !fs::exists(start_file))
    throw pipeline::bad_input(start_file, "no such file: the deck's initial_state names it (relative to the deck's "
                                          "folder); run the stage that writes it first");
  const SolverState start = start_file.empty() ? SolverState{} : load_state(start_file);
  Model started = model;  // messages about the starting state name the file the run started from
  started.initial_state.file = start_file;
  Solver s(std::move(started), start_file.empty() ? nullptr : &start.x);
  const Model& m = s.model();
  if (!opt.restart.empty())
    s.set_state(start, false, false);
  else if (!start_file.empty())
    s.set_state(start, m.initial_state.reset_time, m.initial_state.reset_velocity);
  // A state from past the end (a restart from a longer run) ran 0 steps and wrote its results.
  if (!(s.time() < m.control.end_time))
    throw pipeline::bad_input(start_file, "the run starts at t = " + fmt(s.time()) +
                                              " ms, not before the end time (control.end_time, or --end-time-ms) " +
                                              fmt(m.control.end_time) + " ms (" +
                                              (opt.restart.empty()
                                                   ? "initial_state.reset_time?)"
                                                   : "--restart continues a run in its own time, to a later end_time; "
                                                     "to start a new stage from this state, name it in the deck's "
                                                     "initial_state with reset_time, and leave --restart out)"));
  // An end time in the wrong unit (s read as ms is a factor 1000; 1e300 is a typo) would run for
  // days or for ever: a billion steps is 115 days of the medium_onesize model (~100 steps/s on 2
  // cores, 2026-12-05). Checked before the output directory is made.
  const double steps_needed = (m.control.end_time - s.time()) / s.dt();
  if (steps_needed > 1e9)
    throw pipeline::bad_input(m.name, "control.end_time " + fmt(m.control.end_time) + " ms needs " +
                                          fmt(steps_needed) + " steps of " + fmt(s.dt()) +
                                          " ms, more than 1e9: check its unit (ms)");
  // Mass scaling is for slow (quasi-static) loading, where even a tenfold mass leaves the answer
  // alone; a dt_target in the wrong unit (µs read as ms) scales the mass by ~1e6 and turns the run
  // into a different, far slower-moving problem without a word.
  // (not "added > 1000 physical": from dt_target ~1e154 the added mass is inf, and NaN results
  // followed with exit 0)
  const double physical_mass = s.physical_mass();
  if (!(s.added_mass() <= 1000 * physical_mass))
    throw pipeline::bad_input(m.name, "control.dt_target " + fmt(m.control.dt_target) + " ms adds " +
                                          pipeline::format_number(s.added_mass() / physical_mass) +
                                          " times the model's mass by mass scaling, more than 1000: check its unit (ms)");
  const Control& c = m.control;
  const double out_dt = c.output_interval > 0 ? c.output_interval : c.end_time / 10;
  const double hist_dt = c.history_interval > 0 ? c.history_interval : out_dt / 10;
  std::size_t n_elem = 0;
  for (const auto& p : m.parts) n_elem += p.size();
  const double span = c.end_time - s.time();  // at most one frame and one history row per step
  require_room_for_outputs(m, n_elem, opt.out_dir, std::ceil(std::min(steps_needed, span / out_dt)) + 2,
                           std::ceil(std::min(steps_needed, span / hist_dt)) + 2, opt.write_results);  // whole counts
  std::error_code ec;
  fs::create_directories(opt.out_dir, ec);
  if (!fs::is_directory(opt.out_dir))
    throw pipeline::io_failed(opt.out_dir, fs::exists(opt.out_dir) ? "is a file, not a directory"
                                                                   : "cannot create the output directory: " + ec.message());
  pipeline::require_writable_outputs({(fs::path(opt.out_dir) / "state.bin").string()});  // else found at the end
  pipeline::log("solve", std::to_string(m.n_nodes()) + " nodes, " + std::to_string(n_elem) + " elements, " +
                             std::to_string(m.contacts.size()) + " contact pair(s); stable dt " +
                             fmt(s.stable_dt()) + " ms (part " + (s.step_limiting_part().empty() ? "none" : s.step_limiting_part()) +
                             "), dt " + fmt(s.dt()) + " ms" +
                             (s.contact_dt() != s.dt() ? " (held elements left out; contact stiffness at the step of every element, " +
                                                             fmt(s.contact_dt()) + " ms)" : "") +
                             ", " + fmt(std::ceil(steps_needed)) + " steps; mass " + fmt(s.total_mass()) +
                             " g, added by mass scaling " + fmt(s.added_mass()) + " g (" +
                             fmt(100 * s.added_mass() / std::max(1e-300, s.physical_mass())) +
                             " %); threads " + std::to_string(omp_get_max_threads()));
  // A material far stiffer or lighter than tissue (an E in Pa read as MPa, a ν of 0.4999999)
  // asks millions of steps, and only the ETA line showed it: skin E 6e5 gave stage I 9.4 million
  // steps (33 h), fat ν 0.4999999 about 2 million (6 h). medium_onesize's stages take 15,400 and
  // 36,500.
  if (steps_needed > many_steps) {
    std::string what;
    for (const Part& p : m.parts)
      if (p.name == s.step_limiting_part()) {
        const Material& mat = m.materials[std::size_t(p.material)];
        what = " (material '" + mat.name + "': E " + fmt(mat.E) + " MPa, nu " + fmt(mat.nu) + ", density " +
               fmt(mat.density) + " g/mm3)";
      }
    pipeline::log("solve", "warning: " + fmt(std::ceil(steps_needed)) + " steps, more than " + fmt(many_steps) +
                               ": part '" + s.step_limiting_part() + "'" + what + " sets the step of " + fmt(s.dt()) +
                               " ms; check its units (MPa, g/mm3) and nu (< 0.5; near 0.5 the step shrinks without bound)");
  }
  // 2. Outputs being built. The files of a sound run. An earlier run's are removed first, so none
  // of them can pass for this run's results if it stops (a signal, divergence, a failed write;
  // the state this run started from is kept: it is the user's input); a sound run removes the
  // diverged_* files of an earlier failure.
  const fs::path dir(opt.out_dir);
  const OutDirLock lock(dir);
  const std::string frames_path = (dir / ".results.frames.tmp").string(), results_path = (dir / "results.msh").string();
  std::ofstream frames;
  auto remove_outputs = [&] {
    if (frames.is_open()) frames.close();
    fs::remove(frames_path, ec);
    for (const char* f : sound_run_files)
      if (start_file.empty() || !fs::equivalent(dir / f, start_file, ec)) fs::remove(dir / f, ec);
  };
  remove_outputs();
  if (opt.write_results) frames.open(frames_path);
  std::string energy_csv = "time_ms,kinetic_mJ,internal_mJ,contact_mJ,damping_mJ,external_work_mJ,scheme_term_mJ,"
                           "balance_error_mJ\n";
  std::string forces_csv = "time_ms";
  for (const auto& cp : m.contacts) forces_csv += "," + cp.name + "_Fx," + cp.name + "_Fy," + cp.name + "_Fz";
  for (const auto& g : m.output.history_groups)
    for (const char* k : {"reaction", "section"})
      for (const char* d : {"x", "y", "z"}) forces_csv += "," + g + "_" + k + "_F" + d;
  forces_csv += "\n";
  // 3. Time loop.
  pipeline::Progress progress("solve", std::size_t(std::max(1.0, std::ceil(steps_needed))),
                              opt.progress ? 2.0 : 1e30);
  const double t0 = s.time();
  double next_out = t0, next_hist = t0, emax = 0, max_pen = 0;
  int frame = 0;
  long step0 = s.steps();
  SolverState good = s.state();
  RunSummary sum;
  auto fail = [&](const std::string& why) {
    remove_outputs();
    const std::string diag = (dir / "diverged_state.bin").string();
    save_state(diag, good);
    pipeline::write_text_atomic((dir / "diverged_energy.csv").string(), energy_csv);
    throw pipeline::algorithm_failed(m.name, "diverged at t = " + fmt(s.time()) + " ms (step " +
                                                 std::to_string(s.steps()) + "): " + why + "; last good state (t = " +
                                                 fmt(good.time) + " ms) in " + diag + ", no results written");
  };
  const StopSignals stop_signals;
  while (true) {
    if (stop_signal) {
      remove_outputs();
      throw pipeline::Error(pipeline::ErrorKind::interrupted,
                            m.name + ": stopped by " + signal_name(stop_signal) +
                                " at t = " + fmt(s.time()) + " ms (step " + std::to_string(s.steps()) +
                                "), no results written");
    }
    const bool last = s.time() >= c.end_time;
    if (opt.write_results && (s.time() >= next_out - 1e-12 || last)) {
      errno = 0;
      write_frame(frames, m, s, frame++);
      // A frame that could not be written stops the run now: on a full disk it stepped on to its
      // end (12 minutes for stage II) and said so only then (sweep P).
      if (!frames.flush()) {
        const std::string why = errno ? std::strerror(errno) : "disk full?";
        remove_outputs();
        throw pipeline::io_failed(results_path, "frame " + std::to_string(frame - 1) + " (t = " + fmt(s.time()) +
                                                    " ms) could not be written: " + why + "; no results written");
      }
      next_out = next_time(t0, out_dt, s.time());
    }
    if (last) break;
    // A row at each history time and one at the last step: the tables ended up to one history
    // interval before the end time (198 of stage I's 200 ms), whose state the results show.
    const bool hist = s.time() >= next_hist - 1e-12 || s.time() + s.dt() >= c.end_time;
    if (hist) {
      s.request_energy();
      next_hist = next_time(t0, hist_dt, s.time());
    }
    s.step();
    if (!s.health().empty()) fail(s.health());
    max_pen = std::max(max_pen, s.max_penetration());
    if (hist) {
      const Energies& e = s.energies();
      energy_csv += energy_row(e);
      forces_csv += fmt(e.time);
      for (const auto& cp : s.contacts())
        for (double f : cp.resultant_force()) forces_csv += "," + fmt(f);
      for (const auto& g : m.output.history_groups) {
        for (double f : s.reaction(g)) forces_csv += "," + fmt(f);
        for (double f : s.section_force(g)) forces_csv += "," + fmt(f);
      }
      forces_csv += "\n";
      emax = std::max({emax, e.kinetic + e.internal, std::fabs(e.external), e.contact + e.damping});
      // Below ~1e-9 mJ (a model at rest: the respirator with its rim held and no load had 4e-12
      // mJ) the balance is round-off and the ratio meaningless; a strap's work in stage I is ~mJ.
      constexpr double round_off_energy_mJ = 1e-9;
      if (emax > round_off_energy_mJ && std::fabs(e.balance) > c.energy_tolerance * emax)
        fail("energy balance error " + fmt(e.balance) + " mJ exceeds " + fmt(c.energy_tolerance) +
             " of the largest energy " + fmt(emax) + " mJ");
      good = s.state();
      sum.energies = e;
    }
    // the steps still needed at the present step size: the plan made with the first one ran to
    // 103 % with an ETA of 0 s when contact shrank the step (sweep M)
    const std::size_t done = std::size_t(s.steps() - step0);
    if (s.dt() > 0) progress.set_total(done + std::size_t(std::max(0.0, std::ceil((c.end_time - s.time()) / s.dt()))));
    progress.update(done, "t = " + fmt(s.time()) + " ms");
  }
  // 4. Outputs, now that the run is sound: each atomic, and all or none, results.msh (the largest)
  // first, so that a full disk leaves no state.bin or CSV beside missing results; state.bin last,
  // so that a run restarted from <out-dir>/state.bin keeps that file whatever fails before it.
  const std::string& results = results_path;
  try {
    if (frames.is_open()) {
      frames.close();
      if (!frames) throw pipeline::io_failed(results, "the frames could not be written (disk full?)");
    }
    pipeline::write_all_or_none(
        {{opt.write_results ? results : "",
          [&] {
            write_mesh_msh(m, results, [&](const std::string& tmp) {
              const auto frames_bytes = fs::file_size(frames_path), mesh_bytes = fs::file_size(tmp);
              if (frames_bytes == 0) return;
              {
                std::ofstream out(tmp, std::ios::app | std::ios::binary);
                std::ifstream in(frames_path, std::ios::binary);
                out << in.rdbuf();
              }
              // `out << rdbuf` reports a short copy only when nothing was copied
              if (fs::file_size(tmp) != mesh_bytes + frames_bytes)
                throw pipeline::io_failed(results, "written incompletely (" + std::to_string(fs::file_size(tmp)) +
                                                       " of " + std::to_string(mesh_bytes + frames_bytes) +
                                                       " bytes): disk full or a file size limit?");
            });
          }},
         {(dir / "energy.csv").string(), [&] { pipeline::write_text_atomic((dir / "energy.csv").string(), energy_csv); }},
         {(dir / "forces.csv").string(), [&] { pipeline::write_text_atomic((dir / "forces.csv").string(), forces_csv); }},
         {(dir / "state.bin").string(), [&] { save_state((dir / "state.bin").string(), s.state()); }}});
  } catch (...) {
    remove_outputs();
    throw;
  }
  fs::remove(frames_path, ec);
  for (const char* f : diverged_run_files) fs::remove(dir / f, ec);
  sum.time = s.time();
  sum.steps = s.steps() - step0;
  sum.dt = s.dt();
  sum.stable_dt = s.stable_dt();
  sum.added_mass = s.added_mass();
  sum.total_mass = s.total_mass();
  sum.max_penetration = max_pen;
  sum.wall_s = progress.elapsed_s();
  progress.finish(std::to_string(sum.steps) + " steps to t = " + fmt(sum.time) + " ms");
  return sum;
}

}  // namespace solve
