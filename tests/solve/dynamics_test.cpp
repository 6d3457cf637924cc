// Dynamic verification of the integrator: wave speed, energy conservation, restart hand-off,
// thread-count independence, stability guard.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"
#include "solve/make_block.h"
#include "solve/run.h"
#include "solve/save_state.h"
#include "solve/solver.h"
#include "../bad_input_message.h"
#include "../scratch_dir.h"

namespace {

using solve::ElementType;
namespace fs = std::filesystem;

std::string temp_dir(const std::string& name) {
  const fs::path p = scratch_dir() / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

// A soft block of nx × ny × nz mm in 1 mm cells of irregular wedges, its bottom (zmin) fixed.
solve::Model soft_block_fixed_below(int nx, int ny, int nz) {
  solve::BlockSpec b;
  b.type = ElementType::wedge6;
  b.nx = nx; b.ny = ny; b.nz = nz;
  b.size = {double(nx), double(ny), double(nz)};
  b.jitter = 0.2;
  solve::Model m = solve::make_block(b, {"soft", 1e-3, 0.6, 0.45, false});
  for (int d = 0; d < 3; ++d) m.bcs.push_back({"zmin", d, solve::BcKind::fixed, {}});
  return m;
}

// A small loaded, damped, partly constrained block exercising BCs, loads, damping and the
// periodic dt update (every 7 steps).
solve::Model busy_block() {
  solve::Model m = soft_block_fixed_below(4, 3, 3);
  m.bcs.push_back({"zmax", 0, solve::BcKind::velocity, solve::Curve{{0, 0.5, 1}, {0, 0.3, 0}}});
  m.loads.push_back({"xmax", 2, solve::Curve{{0, 1}, {0, -0.02}}});
  m.control.damping_alpha = 0.2;
  m.control.dt_update_interval = 7;
  m.control.end_time = 2.0;
  return m;
}

// A soft wedge block (2 × 2 × 1 mm, skin) on a fixed rigid hex base (4 × 4 × 1 mm, bone) under
// it, pressed down by 0.01 N on its top face (ramped over ramp_ms, then held); contact pair
// "top_on_base": the block's bottom face (segment-to-surface) on the base's top, damping ratio 0.1.
// The block's groups are prefixed "top_"; damping α = 2 /ms.
struct BlockOnBase {
  int base_cells = 5;              // per side, 1 layer
  int top_cells = 2, top_layers = 2;
  double jitter = 0;               // of the block's interior nodes
  double ramp_ms = 1;
  double friction = 0;
};

solve::Model block_on_rigid_base(const BlockOnBase& spec) {
  solve::BlockSpec base;
  base.nx = spec.base_cells; base.ny = spec.base_cells; base.nz = 1;
  base.size = {4, 4, 1};
  base.origin = {-1, -1, -1};
  solve::Model m = solve::make_block(base, {"bone", 4.5e-3, 1000, 0.3, true});
  solve::BlockSpec top;
  top.type = ElementType::wedge6;
  top.nx = spec.top_cells; top.ny = spec.top_cells; top.nz = spec.top_layers;
  top.size = {2, 2, 1};
  top.jitter = spec.jitter;
  solve::Model t = solve::make_block(top, {"skin", 1.2e-3, 0.6, 0.45, false});
  t.loads.push_back({"zmax", 2, solve::Curve{{0, spec.ramp_ms, 10}, {0, -0.01, -0.01}}});
  solve::append_model(m, t, "top_");
  for (int d = 0; d < 3; ++d) m.bcs.push_back({"all", d, solve::BcKind::fixed, {}});
  m.contacts.push_back({"top_on_base", "top_zmin", "zmax", 0.1, 0.1, spec.friction, false});
  m.control.damping_alpha = 2.0;
  return m;
}

// The values of the last $NodeData block named `name` in a results.msh (one component per node),
// by node tag; empty when there is none or it does not parse.
std::map<long, double> last_node_data(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string head = "$NodeData\n1\n\"" + name + "\"\n";
  const std::size_t at = text.rfind(head);
  if (at == std::string::npos) return {};
  std::istringstream block(text.substr(at + head.size()));
  int n_real = 0, n_int = 0, step = 0, ncomp = 0, n = 0;
  double time = 0;
  block >> n_real >> time >> n_int >> step >> ncomp >> n;
  if (!block || n_real != 1 || n_int != 3 || ncomp != 1) return {};
  std::map<long, double> values;
  for (int k = 0; k < n; ++k) {
    long tag = 0;
    double v = 0;
    if (!(block >> tag >> v)) return {};
    values[tag] = v;
  }
  return values;
}

}  // namespace

// A velocity ramp at the end of a bar (ν = 0, so the bar speed is exactly √(E/ρ)) travels along
// it; the arrival of half the imposed velocity at x = 25 mm and x = 75 mm gives the speed.
// Tolerance 2 % (the issue): with 200 elements the dispersion of the discrete wave is ~0.1 %.
TEST(wave_speed, compression_pulse_travels_at_bar_speed) {
  solve::BlockSpec b;
  b.type = ElementType::hex8;
  b.nx = 200; b.ny = 1; b.nz = 1;
  b.size = {100, 1, 1};
  const double E = 1.0, rho = 1e-3, v0 = 0.01;
  solve::Model m = solve::make_block(b, {"bar", rho, E, 0.0, false});
  m.bcs.push_back({"xmin", 0, solve::BcKind::velocity, solve::Curve{{0, 0.2}, {0, v0}}});
  solve::Solver s(m);
  // probe nodes: bottom-front line nodes at x = 25 and x = 75 (index i along x)
  const int i25 = 50, i75 = 150;
  double t25 = -1, t75 = -1;
  double prev25 = 0, prev75 = 0, tprev = 0;
  while (s.time() < 3.0 && t75 < 0) {
    s.step();
    const double v25 = -s.v()[3 * i25], v75 = -s.v()[3 * i75];  // compression: velocity along +x
    const double a25 = std::fabs(v25), a75 = std::fabs(v75);
    // v is the half-step velocity, at t − dt/2
    const double tm = s.time() - 0.5 * s.dt();
    if (t25 < 0 && a25 >= v0 / 2) t25 = tprev + (v0 / 2 - prev25) / (a25 - prev25) * (tm - tprev);
    if (t75 < 0 && a75 >= v0 / 2) t75 = tprev + (v0 / 2 - prev75) / (a75 - prev75) * (tm - tprev);
    prev25 = a25; prev75 = a75; tprev = tm;
  }
  ASSERT_GT(t25, 0);
  ASSERT_GT(t75, t25);
  const double c = 50.0 / (t75 - t25), c_exact = std::sqrt(E / rho);
  EXPECT_NEAR(c, c_exact, 0.02 * c_exact);
  std::printf("wave speed: measured %.4f mm/ms, sqrt(E/rho) %.4f mm/ms\n", c, c_exact);
}

// Undamped free vibration of a cantilevered irregular wedge block, all modes excited by random
// initial velocities: kinetic + internal energy stays within 1 % of its start over 1000 periods
// of the fundamental mode (central differences are symplectic: the energy error oscillates at
// O((ωΔt)²) and does not drift; measured 0.4 %). The balance, which adds the scheme's own
// O(dt²) term, is the scheme's invariant for a quadratic strain energy at a constant step, so
// what is left in it is the step updates (every 100 steps) and the small strains'
// nonlinearity: within 2e-4 (measured 3.2e-5, 2.6e-6 of it without step updates; 2.0e-3 as
// the balance was until 2026-12-05).
TEST(energy, undamped_free_vibration_conserves_energy_1000_periods) {
  solve::Model m = soft_block_fixed_below(2, 2, 4);
  m.control.end_time = 1e9;
  solve::Solver s(m);
  // initial velocity: bending in x growing with z, plus a little of everything
  solve::SolverState st = s.state();
  std::srand(3);
  for (std::size_t i = 0; i < m.n_nodes(); ++i) {
    const double z = st.X[3 * i + 2];
    if (z == 0) continue;
    st.v[3 * i] = 0.01 * z / 4;
    for (int d = 0; d < 3; ++d) st.v[3 * i + d] += 0.002 * (std::rand() / double(RAND_MAX) - 0.5);
  }
  s.set_state(st);
  // count periods by sign changes of the tip x displacement
  const int tip = int(m.n_nodes()) - 1;
  double last = 0, e0 = -1, worst = 0, worst_balance = 0;
  int crossings = 0;
  long k = 0;
  while (crossings < 2000 + 2) {
    const bool rec = k++ % 50 == 0;
    if (rec) s.request_energy();
    s.step();
    ASSERT_TRUE(s.health().empty()) << s.health();
    if (rec) {
      const double e = s.energies().kinetic + s.energies().internal;
      if (e0 < 0) e0 = e;
      worst = std::max(worst, std::fabs(e - e0) / e0);
      worst_balance = std::max(worst_balance, std::fabs(s.energies().balance) / e0);
    }
    const double u = s.x()[3 * tip] - st.X[3 * tip];
    if (u * last < 0) ++crossings;
    if (u != 0) last = u;
  }
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(worst_balance, 2e-4);
  std::printf("energy test: %ld steps, max relative energy error %.3g, balance error %.3g\n", k, worst, worst_balance);
  RecordProperty("energy_error_max", std::to_string(worst));
}

// Stage hand-off: a run stopped at t/2, saved to a file, reloaded into a new solver and continued
// is bit-identical to a run that never stopped (the state holds everything the step needs).
TEST(save_state, restarted_run_continues_identically) {
  const solve::Model m = busy_block();
  solve::Solver a(m);
  a.run_until(1.5);
  solve::Solver b(m);
  b.run_until(0.7);
  const std::string path = temp_dir("restart") + "/state.bin";
  solve::save_state(path, b.state());
  solve::Solver c(m);
  c.set_state(solve::load_state(path));
  c.run_until(1.5);
  ASSERT_EQ(a.steps(), c.steps());
  EXPECT_EQ(a.time(), c.time());
  for (std::size_t k = 0; k < a.x().size(); ++k) {
    ASSERT_EQ(a.x()[k], c.x()[k]) << k;
    ASSERT_EQ(a.v()[k], c.v()[k]) << k;
  }
}

// A damaged state file is refused naming the file, before any step: a NaN velocity or position
// was run (and ends as "diverged", exit 3, or not at all on a fixed node), bytes after the end were
// ignored, and a vector count past the file's end allocated up to 32 GB before the read failed.
TEST(save_state, damaged_state_files_are_bad_input) {
  solve::Solver b(busy_block());
  b.run_until(0.3);
  const std::string dir = temp_dir("damaged_state"), good = dir + "/state.bin";
  solve::save_state(good, b.state());
  const std::string bytes = pipeline::read_text(good);
  auto message_of = [&](const std::string& name, const std::string& content) -> std::string {
    const std::string path = dir + "/" + name;
    pipeline::write_text_atomic(path, content);
    return bad_input_message([&] { solve::load_state(path); }, path);
  };
  EXPECT_EQ(message_of("good.bin", bytes), "no error");
  EXPECT_EQ(message_of("cut.bin", bytes.substr(0, bytes.size() / 2)), "truncated state file");
  EXPECT_EQ(message_of("joined.bin", bytes + bytes), std::to_string(bytes.size()) +
                                                         " bytes after the end of the state (two files joined?)");
  // The layout: 16-byte magic, 9 scalars, then each vector as a count and its doubles (X, x, v, ...).
  const std::size_t n_X = b.state().X.size(), x_at = 16 + 9 * 8 + 8 + 8 * n_X + 8;
  std::string nan_position = bytes;
  const double nan = std::nan("");
  std::memcpy(&nan_position[x_at + 8 * 5], &nan, 8);
  EXPECT_EQ(message_of("nan.bin", nan_position), "non-finite value in the state's positions at index 5");
  std::string huge_count = bytes;
  const std::uint64_t count = std::uint64_t(1) << 31;
  std::memcpy(&huge_count[16 + 9 * 8], &count, 8);
  EXPECT_EQ(message_of("huge.bin", huge_count), "truncated state file");
  // A v2 file (8 scalars, no contact step) still loads; its contact step is its step.
  std::string v2 = bytes.substr(0, 16 + 8 * 8) + bytes.substr(16 + 9 * 8);
  v2[13] = '2';
  EXPECT_EQ(message_of("v2.bin", v2), "no error");
  const solve::SolverState old_state = solve::load_state(dir + "/v2.bin");
  EXPECT_EQ(old_state.dt, b.state().dt);
  EXPECT_EQ(old_state.dt_contact, 0.0);
  EXPECT_EQ(old_state.x, b.state().x);
}

// Results do not depend on the thread count: element forces go to private arrays and are gathered
// per node in a fixed order, so 1 and 2 threads give bit-identical trajectories.
TEST(solver, results_independent_of_thread_count) {
  // large enough (> kMinParallel elements and nodes) for the loops to really run in parallel
  solve::BlockSpec bs;
  bs.type = ElementType::wedge6;
  bs.nx = 48; bs.ny = 48; bs.nz = 8;  // 36,864 wedges, 21,609 nodes
  bs.size = {48, 48, 8};
  bs.jitter = 0.2;
  solve::Model m = solve::make_block(bs, {"soft", 1e-3, 0.6, 0.45, false});
  m.bcs.push_back({"zmin", 2, solve::BcKind::fixed, {}});
  m.bcs.push_back({"zmax", 2, solve::BcKind::velocity, solve::Curve{{0, 0.1}, {0, -0.5}}});
  m.control.damping_alpha = 0.1;
  m.control.dt_update_interval = 10;
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  solve::Solver a(m);
  a.run_until(0.3);
  omp_set_num_threads(2);
  solve::Solver b(m);
  b.run_until(0.3);
  omp_set_num_threads(saved);
  ASSERT_EQ(a.steps(), b.steps());
  ASSERT_GT(a.steps(), 50);
  for (std::size_t k = 0; k < a.x().size(); ++k) ASSERT_EQ(a.x()[k], b.x()[k]) << k;
  // the energy is a reduction over threads: equal up to round-off only
  EXPECT_NEAR(a.internal_energy(), b.internal_energy(), 1e-12 * a.internal_energy());
}

namespace {

// Runs `steps` steps with the energy balance checked at each, as solve's guard does with a
// history interval of one step; the worst |balance| / largest energy so far.
double worst_balance_every_step(solve::Solver& s, int steps, const char* what) {
  double emax = 0, worst = 0;
  for (int k = 0; k < steps; ++k) {
    s.request_energy();
    s.step();
    EXPECT_TRUE(s.health().empty()) << s.health();
    const solve::Energies& e = s.energies();
    emax = std::max({emax, e.kinetic + e.internal, std::fabs(e.external)});
    if (emax > 0) worst = std::max(worst, std::fabs(e.balance) / emax);
  }
  std::printf("%s: %d steps to t = %.3g ms, largest energy %.3g mJ, worst balance %.3g of it\n", what, steps,
              s.time(), emax, worst);
  EXPECT_GT(emax, 0);
  return worst;
}

}  // namespace

// Starts that are not smooth are sound runs, and the energy balance checked at every step from
// the first must say so, far below solve's default guard (5 % of the largest energy so far). The
// balance includes the central-difference scheme's own term (solver.cpp), with which it is
// exact for a quadratic strain energy at a constant step, so what is left is the nonlinear
// response (the velocity jump compresses the block by 11 %) and the step updates. Bounds 1e-3,
// 1e-4 and 1e-4; measured: velocity jump 1.3e-4, load jump 6.9e-6, restart from a moving state
// 1.3e-6. With the kinetic energy at the mean velocity and no such term, as until 2026-12-05:
// 0.178 (m·v²/8 off for good; solve stopped the assembled medium_onesize model as diverged at
// step 3), 5.7e-3 and 5.9e-4. Taking t_0 as uncentred instead (tried and reviewed the same day)
// fixed the first but gave 0.091 for the load jump and a first-order error after the restart.
TEST(energy, balance_holds_through_velocity_and_load_jumps_and_a_moving_restart) {
  // a 3 × 3 × 4 mm block, undamped (the default damping_alpha, 0)
  const auto fixed_soft_block = [] { return soft_block_fixed_below(3, 3, 4); };
  {
    solve::Model m = fixed_soft_block();
    m.bcs.push_back({"zmax", 2, solve::BcKind::velocity, solve::Curve::constant(-0.2)});
    solve::Solver s(m);
    EXPECT_LT(worst_balance_every_step(s, 300, "velocity jump at t = 0"), 1e-3);
  }
  {
    solve::Model m = fixed_soft_block();
    m.loads.push_back({"zmax", 0, solve::Curve::constant(0.02)});
    solve::Solver s(m);
    EXPECT_LT(worst_balance_every_step(s, 300, "load jump at t = 0"), 1e-4);
  }
  {
    // a later stage started from a moving state (reset_time, velocities kept)
    solve::Model m = fixed_soft_block();
    m.loads.push_back({"zmax", 0, solve::Curve::constant(0.02)});
    solve::Solver first(m);
    for (int k = 0; k < 40; ++k) first.step();
    solve::Model later = fixed_soft_block();
    later.loads.push_back({"zmax", 1, solve::Curve::constant(0.02)});
    solve::Solver s(later);
    s.set_state(first.state(), true, false);
    EXPECT_LT(worst_balance_every_step(s, 300, "restart from a moving state"), 1e-4);
  }
}

// A restart keeps the saved step, and reports the saved state's stable step beside it: it reported
// the reference geometry's, measured before the state was set (sweep Q). Saved where the first run
// had just measured its own (every dt_update_interval = 7 steps), the two are the same number.
TEST(save_state, a_restart_reports_the_saved_states_stable_step) {
  solve::Solver first(busy_block());
  for (int k = 0; k < 70; ++k) first.step();
  solve::Solver restarted(busy_block());
  const double at_reference = restarted.stable_dt();
  restarted.set_state(first.state());
  std::printf("stable step: reference geometry %.9g ms, saved state %.9g ms, restarted %.9g ms\n", at_reference,
              first.stable_dt(), restarted.stable_dt());
  EXPECT_NE(first.stable_dt(), at_reference);  // the block has deformed
  EXPECT_EQ(restarted.stable_dt(), first.stable_dt());
  EXPECT_EQ(restarted.dt(), first.dt());
}

// A later stage that starts at rest (initial_state with reset_velocity, the saved time kept) from
// a moving state: the deck's initial velocity applies (it was dropped: the README's example
// respirator started at rest) and the energy balance is measured from there (the kinetic energy
// removed had stayed in it as an error, enough to stop a run as diverged).
TEST(save_state, reset_velocity_applies_the_decks_initial_velocity_and_restarts_the_balance) {
  solve::Model m = soft_block_fixed_below(3, 3, 4);
  m.loads.push_back({"zmax", 0, solve::Curve::constant(0.02)});
  solve::Solver first(m);
  for (int k = 0; k < 40; ++k) first.step();
  solve::Model later = soft_block_fixed_below(3, 3, 4);
  later.initial_velocities.push_back({"zmax", {0, 0, -0.05}});
  solve::Solver s(later);
  s.set_state(first.state(), false, true);
  EXPECT_EQ(s.time(), first.time());
  std::vector<char> top(later.n_nodes(), 0);
  for (int id : later.group("zmax")) top[id] = 1;
  for (int id = 0; id < int(later.n_nodes()); ++id)
    for (int i = 0; i < 3; ++i) EXPECT_EQ(s.v()[3 * id + i], top[id] && i == 2 ? -0.05 : 0.0) << "node " << id << " dof " << i;
  // as the velocity jump at t = 0 above
  EXPECT_LT(worst_balance_every_step(s, 300, "reset velocity, saved time kept"), 1e-3);
}

// Stability guard: crushing a block at 100 mm/ms inverts elements within a few steps; the run
// stops with an algorithm error, writes the diagnostic state and no results file. The directory
// holds the outputs of an earlier sound run: they go too, so nothing there passes for results of
// the diverged run.
TEST(run, guard_stops_diverging_run_without_results) {
  solve::Model m = busy_block();
  const std::string dir = temp_dir("guard");
  solve::RunOptions o;
  o.out_dir = dir;
  o.progress = false;
  solve::run(m, o);
  ASSERT_TRUE(fs::exists(dir + "/results.msh"));
  m.bcs.push_back({"zmax", 2, solve::BcKind::velocity, solve::Curve::constant(-100.0)});
  try {
    solve::run(m, o);
    FAIL() << "no error";
  } catch (const pipeline::Error& e) {
    EXPECT_EQ(e.kind, pipeline::ErrorKind::algorithm);
    EXPECT_NE(std::string(e.what()).find("diverged"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(dir + "/diverged_state.bin"));
  for (const char* f : {"results.msh", "state.bin", "energy.csv", "forces.csv"})
    EXPECT_FALSE(fs::exists(dir + "/" + f)) << f;
}

// Energy guard: the balance error of a healthy run is small but not zero; a tolerance of 1e-12
// of the largest energy must trip it.
TEST(run, guard_trips_on_energy_balance_error) {
  solve::Model m = busy_block();
  m.control.energy_tolerance = 1e-12;
  const std::string dir = temp_dir("energy_guard");
  solve::RunOptions o;
  o.out_dir = dir;
  EXPECT_THROW(solve::run(m, o), pipeline::Error);
  EXPECT_FALSE(fs::exists(dir + "/results.msh"));
  // and with the default tolerance the same run is sound and writes everything
  m.control.energy_tolerance = 0.05;
  const solve::RunSummary s = solve::run(m, o);
  EXPECT_GT(s.steps, 0);
  EXPECT_TRUE(fs::exists(dir + "/results.msh"));
  EXPECT_TRUE(fs::exists(dir + "/state.bin"));
  EXPECT_TRUE(fs::exists(dir + "/energy.csv"));
}

// Below 1e-9 mJ the balance is round-off, and the guard stays out of it: a respirator at rest
// (4e-12 mJ of round-off) was reported as diverged. The busy block driven a million times more
// gently has its energies 1e12 times smaller (~1e-14 mJ) and about the same relative balance
// error: the 1e-12 tolerance that trips the full-size run (previous test) lets it finish.
TEST(run, guard_leaves_a_run_with_round_off_energies_alone) {
  solve::Model m = busy_block();
  for (auto& b : m.bcs)
    for (double& v : b.curve.value) v *= 1e-6;
  for (auto& l : m.loads)
    for (double& v : l.curve.value) v *= 1e-6;
  m.control.energy_tolerance = 1e-12;
  solve::RunOptions o;
  o.out_dir = temp_dir("round_off_guard");
  o.progress = false;
  const solve::RunSummary s = solve::run(m, o);
  EXPECT_GT(s.energies.kinetic + s.energies.internal, 0.0);
  EXPECT_LT(s.energies.kinetic + s.energies.internal, 1e-9);
}

// The integrator drives a contact pair: a soft block pushed with 0.01 N onto a fixed rigid base
// (non-matching meshes) comes to rest carrying the load through contact. At the quasi-static end
// (damped, 10 decay times after the ramp) the resultant contact force and the base reaction equal
// the load within 1 % (residual inertia ~ e^-10), and the mean contact pressure is F/A.
TEST(solver, contact_pair_carries_load_to_rigid_base) {
  BlockOnBase spec;
  spec.top_cells = 4;
  spec.jitter = 0.1;
  solve::Model m = block_on_rigid_base(spec);
  m.control.end_time = 6.0;
  // keep the top block from drifting sideways (frictionless contact): x/y of one edge
  m.bcs.push_back({"top_xmin", 0, solve::BcKind::fixed, {}});
  m.bcs.push_back({"top_ymin", 1, solve::BcKind::fixed, {}});
  solve::Solver s(m);
  s.run_until(6.0);
  ASSERT_TRUE(s.health().empty()) << s.health();
  const auto fc = s.contacts()[0].resultant_force();
  EXPECT_NEAR(fc[2], 0.01, 1e-4);
  // the support holds the base up against the pushed block: +0.01 N
  EXPECT_NEAR(s.reaction("all")[2], 0.01, 1e-4);
  // The pressure under the block is F/A = 0.01 N / 4 mm² = 2.5e-3 MPa: frictionless contact under
  // a uniform top load is uniaxial stress. The median master node in contact is within 5 % of it
  // (measured 2.53e-3; the jittered mesh scatters single nodes by ±15 %); nodes along the
  // footprint's edge, which gather part of a slave facet's area, read up to 1.7x (4.2e-3), so 2x
  // bounds them all.
  std::vector<double> p;
  for (double v : s.contact_pressure())
    if (v > 0) p.push_back(v);
  ASSERT_GE(p.size(), 9u);  // the 2 x 2 mm footprint covers at least the base's 3 x 3 nodes
  std::sort(p.begin(), p.end());
  const double f_over_a = 0.01 / 4;
  EXPECT_NEAR(p[p.size() / 2], f_over_a, 0.05 * f_over_a);
  EXPECT_GT(p.front(), 0.5 * f_over_a);
  EXPECT_LT(p.back(), 2.0 * f_over_a);
  EXPECT_LT(s.max_penetration(), 0.05);
  // the same model through run(): the energy balance (with contact work) stays within the guard
  solve::RunOptions o;
  o.out_dir = temp_dir("contact_run");
  o.progress = false;
  const solve::RunSummary r = solve::run(m, o);
  const solve::Energies& e = r.energies;
  std::printf("contact run: kinetic %.3g internal %.3g contact %.3g damping %.3g external %.3g balance %.3g mJ\n",
              e.kinetic, e.internal, e.contact, e.damping, e.external, e.balance);
  EXPECT_LT(std::fabs(e.balance), 0.01 * e.external);
  // What results.msh holds as contact_pressure at the end is that pressure: node by node the
  // Solver's above (the same steps to the same time), so its median is F/A too. No test read the
  // values in results.msh: the shear field written under the pressure's name passed (sweep L).
  const std::map<long, double> written = last_node_data(o.out_dir + "/results.msh", "contact_pressure");
  ASSERT_EQ(written.size(), m.n_nodes());
  const std::vector<double> pressure = s.contact_pressure();
  std::vector<double> loaded;
  for (std::size_t i = 0; i < m.n_nodes(); ++i) {
    ASSERT_EQ(written.count(m.node_tag(i)), 1u) << "node " << m.node_tag(i);
    const double v = written.at(m.node_tag(i));
    EXPECT_NEAR(v, pressure[i], 1e-6 * f_over_a) << "node " << m.node_tag(i);
    if (v > 0) loaded.push_back(v);
  }
  ASSERT_GE(loaded.size(), 9u);
  std::sort(loaded.begin(), loaded.end());
  EXPECT_NEAR(loaded[loaded.size() / 2], f_over_a, 0.05 * f_over_a);
}

// No volumetric locking: the static tip deflection of a cantilever (20 × 1 × 2 elements, end
// load, dynamic relaxation) barely depends on ν for a slender beam (Timoshenko: shear term ~2 %
// here). A locking element at ν = 0.49 is several times too stiff. Accepted: the ν = 0.49 tip
// deflection is within 20 % of the ν = 0.3 one (hourglass stiffness scales with μ = E/2(1+ν), a
// ~13 % effect on this coarse mesh, plus the Poisson effect on the cross-section).
TEST(locking, cantilever_at_nu_049_does_not_lock) {
  auto tip = [](ElementType t, double nu) {
    solve::BlockSpec b;
    b.type = t;
    b.nx = 20; b.ny = 1; b.nz = 2;
    b.size = {10, 1, 1};
    solve::Model m = solve::make_block(b, {"soft", 1e-5, 1.0, nu, false});
    for (int d = 0; d < 3; ++d) m.bcs.push_back({"xmin", d, solve::BcKind::fixed, {}});
    m.loads.push_back({"xmax", 2, solve::Curve{{0, 2, 100}, {0, -1e-4, -1e-4}}});
    m.control.damping_alpha = 3.0;
    solve::Solver s(m);
    s.run_until(12.0);
    EXPECT_TRUE(s.health().empty());
    double w = 0;
    const auto& g = m.group("xmax");
    for (int id : g) w += (s.x()[3 * id + 2] - m.X[3 * id + 2]) / double(g.size());
    return w;
  };
  for (ElementType t : {ElementType::wedge6, ElementType::hex8}) {
    const double w03 = tip(t, 0.3), w049 = tip(t, 0.49);
    // beam theory P L³ / (3 E I) = 1e-4 · 1000 / (3 · 1/12) = 0.4 mm
    std::printf("%s cantilever tip: nu=0.3 %.4f mm, nu=0.49 %.4f mm (beam theory 0.4)\n", solve::element_name(t),
                w03, w049);
    ASSERT_LT(w03, 0);
    EXPECT_GT(w049 / w03, 0.8) << solve::element_name(t);
    EXPECT_LT(w049 / w03, 1.2) << solve::element_name(t);
    // and near beam theory (+ shear deformation and the coarse mesh's bending error): 25 %
    EXPECT_NEAR(-w049, 0.4, 0.1) << solve::element_name(t);
  }
}

// Mass scaling: a target step 5× the stable one adds mass (reported), the run stays stable and
// reaches the same static state (the static answer does not depend on mass; 1e-4 relative after
// damping out the dynamics).
TEST(mass_scaling, target_step_adds_mass_and_keeps_static_answer) {
  solve::Model m = busy_block();
  m.bcs.erase(m.bcs.begin() + 3);  // keep only the fixed base and the load
  m.control.damping_alpha = 2.0;
  m.control.end_time = 10;
  solve::Solver ref(m);
  const double dt0 = ref.dt();
  m.control.dt_target = 5 * dt0;
  solve::Solver s(m);
  EXPECT_EQ(s.dt(), 5 * dt0);
  EXPECT_GT(s.added_mass(), 0);
  EXPECT_NEAR(s.total_mass() - s.added_mass(), ref.total_mass(), 1e-12 * ref.total_mass());
  ref.run_until(8);
  s.run_until(8);
  ASSERT_TRUE(s.health().empty()) << s.health();
  const auto& xa = ref.x();
  const auto& xb = s.x();
  double umax = 0, err = 0;
  for (std::size_t k = 0; k < xa.size(); ++k) {
    umax = std::max(umax, std::fabs(xa[k] - m.X[k]));
    err = std::max(err, std::fabs(xa[k] - xb[k]));
  }
  EXPECT_GT(umax, 1e-3);
  EXPECT_LT(err, 1e-3 * umax);
}

// The run's first line names the part whose element sets the step: a skin E in Pa read as MPa
// (6e5) asked 9.4 million steps of medium_onesize's stage I, and only the ETA showed it.
TEST(stable_step, the_part_that_sets_it_is_named) {
  solve::Model m = busy_block();
  EXPECT_EQ(solve::Solver(m).step_limiting_part(), "block");
  solve::BlockSpec small;
  small.nx = 4; small.ny = 4; small.nz = 4;
  small.origin = {10, 0, 0};
  small.part = "stiff";
  solve::append_model(m, solve::make_block(small, {"stiff", 1e-3, 1000, 0.3, false}), "s_");
  for (int d = 0; d < 3; ++d) m.bcs.push_back({"s_zmin", d, solve::BcKind::fixed, {}});
  const solve::Solver both(m);
  EXPECT_EQ(both.step_limiting_part(), m.parts.back().name);
  EXPECT_NE(both.step_limiting_part().find("stiff"), std::string::npos) << both.step_limiting_part();
}

// Elements whose every node `fixed` holds in x, y and z cannot deform, and no longer bound the
// step: stage I of medium_onesize holds the head and the respirator, whose elements set its step
// at a quarter of the straps'. The contact stiffness keeps the step of every element, so the
// same base held by a prescribed velocity of 0 (which does not count as held: the old step)
// gives the same contact, and the longer step stops at the penalty's limit ω·dt = √(1+ξ²) − ξ.
// The soft block pressed on a stiff deformable base (E 1000 MPa, held) comes to rest under its
// 0.01 N: both runs' displacements agree within 1 % of the largest (measured: see the printed
// line), and the contact force equals the load within 1 % at 10 ms (damped, α = 2/ms).
TEST(stable_step, held_elements_do_not_bound_it) {
  auto model = [](bool held_by_fixed) {
    BlockOnBase spec;
    spec.base_cells = 4;
    solve::Model m = block_on_rigid_base(spec);
    m.materials[0].rigid = false;  // a stiff deformable base: its elements set the step
    m.bcs.erase(std::remove_if(m.bcs.begin(), m.bcs.end(), [](const solve::NodeBc& b) { return b.group == "all"; }),
                m.bcs.end());
    for (int d = 0; d < 3; ++d)
      m.bcs.push_back(held_by_fixed ? solve::NodeBc{"all", d, solve::BcKind::fixed, {}}
                                    : solve::NodeBc{"all", d, solve::BcKind::velocity, solve::Curve::constant(0)});
    m.control.end_time = 10;
    return m;
  };
  solve::Solver held(model(true)), moving(model(false));
  EXPECT_EQ(held.contact_dt(), moving.dt());
  EXPECT_EQ(moving.contact_dt(), moving.dt());
  const double s_pen = 0.1, xi = 0.1, limit = (std::sqrt(1 + xi * xi) - xi) / std::sqrt(s_pen);
  EXPECT_NEAR(held.dt(), limit * moving.dt(), 1e-12 * held.dt());  // the skin alone allows more
  EXPECT_LT(held.dt(), 0.9 * held.stable_dt());
  EXPECT_EQ(held.step_limiting_part(), "top_block");
  EXPECT_EQ(moving.step_limiting_part(), "block");
  held.run_until(10);
  moving.run_until(10);
  ASSERT_TRUE(held.health().empty()) << held.health();
  ASSERT_TRUE(moving.health().empty()) << moving.health();
  double umax = 0, diff = 0;
  for (std::size_t k = 0; k < held.x().size(); ++k) {
    umax = std::max(umax, std::fabs(moving.x()[k] - moving.model().X[k]));
    diff = std::max(diff, std::fabs(held.x()[k] - moving.x()[k]));
  }
  EXPECT_GT(umax, 1e-4);
  EXPECT_LT(diff, 0.01 * umax);
  for (const solve::Solver* s : {&held, &moving})
    EXPECT_NEAR(s->contacts()[0].resultant_force()[2], 0.01, 1e-4);
  std::printf("held base: %ld steps of %.6g ms (contact step %.6g ms) against %ld of %.6g ms; largest displacement "
              "%.4g mm, largest difference %.3g mm; contact force %.6f / %.6f N\n",
              held.steps(), held.dt(), held.contact_dt(), moving.steps(), moving.dt(), umax, diff,
              held.contacts()[0].resultant_force()[2], moving.contacts()[0].resultant_force()[2]);
  // A restart continues a held run bit-identically: the state keeps the contact step.
  solve::Solver first(model(true)), resumed(model(true));
  first.run_until(5);
  const std::string path = temp_dir("held_restart") + "/state.bin";
  solve::save_state(path, first.state());
  resumed.set_state(solve::load_state(path));
  EXPECT_EQ(resumed.contact_dt(), first.contact_dt());
  first.run_until(10);
  resumed.run_until(10);
  ASSERT_EQ(first.steps(), resumed.steps());
  EXPECT_EQ(first.x(), resumed.x());
  EXPECT_EQ(first.x(), held.x());
  // Every element held and no contact: the step stays the elements' own (it came out infinite).
  solve::Model still = model(true);
  still.contacts.clear();
  for (int d = 0; d < 3; ++d) still.bcs.push_back({"top_all", d, solve::BcKind::fixed, {}});
  still.loads.clear();
  const solve::Solver all_held(still), fresh(model(false));
  EXPECT_EQ(all_held.dt(), fresh.dt());
  EXPECT_EQ(all_held.stable_dt(), fresh.stable_dt());
}

// Penetration guard: the block pressed on the base penetrates ~2 µm; a tolerance of 0.1 µm stops
// the run with the diagnostic state and no results.
TEST(run, guard_trips_on_penetration) {
  BlockOnBase spec;
  spec.base_cells = 3;
  solve::Model m = block_on_rigid_base(spec);
  m.control.end_time = 3;
  m.control.penetration_tolerance = 1e-4;
  solve::RunOptions o;
  o.out_dir = temp_dir("pen_guard");
  o.progress = false;
  try {
    solve::run(m, o);
    FAIL() << "no error";
  } catch (const pipeline::Error& e) {
    EXPECT_NE(std::string(e.what()).find("penetration"), std::string::npos) << e.what();
    // the message names the pair and where its deepest point is: on the block's bottom face
    // (x, y in [0, 2], z = 0 less the ~2 µm penetration; printed to 0.01 mm)
    const std::string what = e.what();
    EXPECT_NE(what.find("pair '" + m.contacts.at(0).name + "'"), std::string::npos) << what;
    const auto at = what.find("slave point at ");
    ASSERT_NE(at, std::string::npos) << what;
    double x = -1, y = -1, z = -1;
    ASSERT_EQ(std::sscanf(what.c_str() + at + 15, "%lf %lf %lf", &x, &y, &z), 3) << what;
    EXPECT_GE(x, 0.0); EXPECT_LE(x, 2.0);
    EXPECT_GE(y, 0.0); EXPECT_LE(y, 2.0);
    EXPECT_NEAR(z, 0.0, 0.006) << what;
  }
  EXPECT_TRUE(fs::exists(o.out_dir + "/diverged_state.bin"));
  EXPECT_FALSE(fs::exists(o.out_dir + "/results.msh"));
}

// The block on its base pushed sideways as well, with Coulomb friction (μ = 0.3): the side push
// stays below μ·F_n, so the contact points hold elastic stick forces.
namespace {
solve::Model block_on_base_with_friction() {
  BlockOnBase spec;
  spec.top_cells = 3;
  spec.jitter = 0.1;
  spec.ramp_ms = 0.5;
  spec.friction = 0.3;
  solve::Model m = block_on_rigid_base(spec);
  m.loads.push_back({"top_zmax", 0, solve::Curve{{0, 0.5, 1, 10}, {0, 0, 0.002, 0.002}}});
  m.control.end_time = 2.0;
  return m;
}
}  // namespace

// The slave group is a surface (the block's bottom face): the Solver hands its facets to the
// contact pair, which then integrates over them (9 points per facet by default); a node group
// without facets stays node-to-surface (one point per node).
TEST(solver, contact_slave_surface_fills_slave_facets) {
  solve::Model m = block_on_base_with_friction();
  const std::size_t facets = m.surfaces.at("top_zmin").size();
  m.node_groups["top_bottom_nodes"] = m.group("top_zmin");  // same nodes, no surface
  m.contacts.push_back({"nodes_on_base", "top_bottom_nodes", "zmax", 0.1, 0.1, 0.0, false});
  solve::Solver s(m);
  ASSERT_EQ(s.contacts().size(), 2u);
  EXPECT_EQ(s.contacts()[0].spec().slave_tris, m.surfaces.at("top_zmin"));
  EXPECT_EQ(s.contacts()[0].n_points(), 9 * facets);
  EXPECT_TRUE(s.contacts()[1].spec().slave_tris.empty());
  EXPECT_EQ(s.contacts()[1].n_points(), m.group("top_zmin").size());
}

// Stage hand-off with friction: the stick forces are part of the state, so a run restarted from
// state.bin continues bit-identically. Without the contact history (an old v1 file) the sticking
// restarts from zero and the trajectory differs: checked, so this test can fail.
TEST(save_state, restarted_run_with_friction_continues_identically) {
  const solve::Model m = block_on_base_with_friction();
  solve::Solver a(m);
  a.run_until(2.0);
  ASSERT_EQ(a.health(), "");
  double stick = 0;
  for (double t : a.contact_shear()) stick = std::max(stick, t);
  EXPECT_GT(stick, 0.0);  // friction is active
  solve::Solver b(m);
  b.run_until(1.2);
  const std::string path = temp_dir("restart_friction") + "/state.bin";
  solve::save_state(path, b.state());
  const solve::SolverState saved = solve::load_state(path);
  ASSERT_EQ(saved.contact_history.size(), 1u);
  solve::Solver c(m);
  c.set_state(saved);
  c.run_until(2.0);
  ASSERT_EQ(a.steps(), c.steps());
  for (std::size_t k = 0; k < a.x().size(); ++k) {
    ASSERT_EQ(a.x()[k], c.x()[k]) << k;
    ASSERT_EQ(a.v()[k], c.v()[k]) << k;
  }
  // and the works the file carries come back as saved (contact and damping swapped in it passed,
  // sweep N: energy.csv's columns after a --restart)
  const solve::SolverState before = b.state();
  EXPECT_EQ(saved.e_contact, before.e_contact);
  EXPECT_EQ(saved.e_damping, before.e_damping);
  EXPECT_EQ(saved.w_external, before.w_external);
  EXPECT_NE(before.e_contact, before.e_damping);  // else a swap would not show
  solve::SolverState forgetful = saved;
  forgetful.contact_history.clear();
  solve::Solver d(m);
  d.set_state(forgetful);
  d.run_until(2.0);
  double diff = 0;
  for (std::size_t k = 0; k < a.x().size(); ++k) diff = std::max(diff, std::fabs(a.x()[k] - d.x()[k]));
  EXPECT_GT(diff, 0.0);
}

// Several pairs press on one surface (stage II has three on head_skin): the pressure the Solver
// reports, and results.msh writes, is their sum node by node, not the last pair's (that slip
// passed every one-pair test: sweep L). The block on its base twice over: once through its
// bottom face, once through the same nodes as a node group; both pairs carry load.
TEST(solver, pressure_and_shear_of_several_pairs_add_up) {
  solve::Model m = block_on_base_with_friction();
  m.node_groups["top_bottom_nodes"] = m.group("top_zmin");
  m.contacts.push_back({"nodes_on_base", "top_bottom_nodes", "zmax", 0.1, 0.1, 0.3, false});
  solve::Solver s(m);
  s.run_until(1.0);
  ASSERT_TRUE(s.health().empty()) << s.health();
  ASSERT_EQ(s.contacts().size(), 2u);
  const std::vector<double> p = s.contact_pressure(), q = s.contact_shear();
  for (std::size_t c = 0; c < 2; ++c)
    EXPECT_GE(std::count_if(s.contacts()[c].pressure().begin(), s.contacts()[c].pressure().end(),
                            [](double v) { return v > 0; }),
              9)
        << "pair " << c << " carries no load: the test would not see a lost pair";
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_DOUBLE_EQ(p[i], s.contacts()[0].pressure()[i] + s.contacts()[1].pressure()[i]) << i;
    EXPECT_DOUBLE_EQ(q[i], s.contacts()[0].shear()[i] + s.contacts()[1].shear()[i]) << i;
  }
}

// Progress counts the steps still needed at the present step size. A block crushed to 60 % of its
// height shrinks its stable step as it goes, so the run takes more steps than planned at the
// start; its progress never passes 100 % (stage I printed "16168/15705 (103%) ... ETA 0.0 s":
// sweep M). Without progress lines (o.progress false) only the lines at 100 % are printed.
// A prescribed velocity is taken at the half step the central-difference update moves with, so
// a velocity rising linearly, v = a·t, gives exactly x = a·t²/2 whatever the steps (Σ dt (t + dt/2)
// = Σ (t_{n+1}² − t_n²)/2). Sampled at the step's start it lagged by a·t·dt/2 and passed every test
// (sweep N).
TEST(velocity_bc, a_linear_velocity_moves_its_nodes_by_the_exact_integral) {
  solve::Model m = soft_block_fixed_below(2, 2, 2);
  const double a = -0.2;  // [mm/ms²]
  m.bcs.push_back({"zmax", 2, solve::BcKind::velocity, solve::Curve{{0, 2}, {0, 2 * a}}});
  m.control.end_time = 1.0;
  solve::Solver s(m);
  s.run_until(1.0);
  ASSERT_EQ(s.health(), "");
  const double t = s.time();
  for (int node : m.group("zmax")) {
    const std::size_t z = 3 * std::size_t(node) + 2;
    EXPECT_NEAR(s.x()[z] - m.X[z], 0.5 * a * t * t, 1e-12) << node;
  }
}

TEST(run, progress_follows_a_shrinking_step_and_stays_within_100_percent) {
  solve::Model m = soft_block_fixed_below(2, 2, 4);
  m.bcs.push_back({"zmax", 2, solve::BcKind::velocity, solve::Curve{{0, 0.1, 4}, {0, -0.4, -0.4}}});
  m.control.damping_alpha = 1.0;
  m.control.dt_update_interval = 5;
  m.control.end_time = 4.0;
  solve::RunOptions o;
  o.out_dir = temp_dir("shrinking_step");
  o.progress = false;
  ::testing::internal::CaptureStderr();
  const solve::RunSummary r = solve::run(m, o);
  const std::string log = ::testing::internal::GetCapturedStderr();
  long planned = -1;
  const auto plan = log.find(" steps; mass");
  ASSERT_NE(plan, std::string::npos) << log;
  planned = std::stol(log.substr(log.rfind(", ", plan) + 2));
  EXPECT_GT(r.steps, planned) << "the stable step was not updated as the block compressed (and this test would not see the overshoot)\n" << log;
  std::size_t percents = 0;
  for (std::size_t at = log.find("%)"); at != std::string::npos; at = log.find("%)", at + 1), ++percents)
    EXPECT_LE(std::stod(log.substr(log.rfind('(', at) + 1)), 100.0) << log;
  EXPECT_GE(percents, 1u) << log;
}
