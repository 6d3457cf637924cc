// Element throughput of the explicit solver: wedge (6-node pentahedron) internal-force updates per
// second, on 1 and 2 threads, the usual explicit-code figure (issue 5: ≥ 5 M/s on one core,
// ≥ 1.7× that on two). Also the cost of a whole solver step (forces, gather, constraints, update)
// per element. A plain program (not Google Benchmark): it prints the figures the README quotes.
//
// Sample run:  bench_elements --cells 100 --seconds 2
#include <omp.h>

#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "pipeline/cli.h"
#include "solve/internal/elements.h"
#include "solve/make_block.h"
#include "solve/solver.h"

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

// Runs f repeatedly for at least `min_s` seconds; returns calls per wall second and, in
// *per_cpu_s, calls per CPU second of the process (per core: on a machine shared with other
// jobs the wall figure drops, the CPU figure does not).
template <class F>
double rate(F&& f, double min_s, double* per_cpu_s) {
  f();  // warm-up (first touch, caches)
  long n = 0;
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = cpu_seconds();
  do {
    f();
    ++n;
  } while (seconds_since(t0) < min_s);
  *per_cpu_s = n / (cpu_seconds() - c0);
  return n / seconds_since(t0);
}

}  // namespace

int main(int argc, char** argv) {
  int nx = 100;
  double min_s = 2.0;
  pipeline::Cli cli("bench_elements", "Wedge internal-force updates per second on 1 and 2 threads, and the cost of a whole "
                                      "solver step, on a jittered block of wedges.");
  cli.option("-n", "--cells", &nx, "cells along x and y (10 along z, 2 wedges each)", 2, 1000)
      .option("-s", "--seconds", &min_s, "least time per measured case [s]", 0.01, 600.0);
  return pipeline::run_main(cli, argc, argv, [&] {
    solve::BlockSpec b;
    b.type = solve::ElementType::wedge6;
    b.nx = nx; b.ny = nx; b.nz = 10;
    b.size = {double(nx), double(nx), 10};
    b.jitter = 0.2;
    solve::Model m = solve::make_block(b, {"fat", 1e-3, 0.015, 0.48, false});
    const solve::internal::ElementBlock blk =
        solve::internal::setup_block(m.parts[0], 0, m.materials[0], m.X.data(), 0.1, "bench");
    const std::size_t ne = blk.size();
    // a deformed state: uniform stretch plus noise, so every element does real work
    std::vector<double> x = m.X;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(-0.01, 0.01);
    for (std::size_t k = 0; k < x.size(); ++k) x[k] = 1.02 * x[k] + U(rng);
    std::vector<double> fe(ne * 6 * 3);
    double load[3] = {0, 0, 0};
    getloadavg(load, 3);
    std::printf("bench_elements: %zu wedges, %zu nodes; load average %.1f (wall figures need an idle machine)\n", ne,
                m.n_nodes(), load[0]);
    double r1 = 0;
    for (int threads : {1, 2}) {
      omp_set_num_threads(threads);
      double cpu = 0;
      const double calls = rate([&] { solve::internal::forces_for_elems(blk, x.data(), fe.data()); }, min_s, &cpu);
      const double per_s = calls * double(ne);
      if (threads == 1) r1 = per_s;
      std::printf("element kernel, %d thread(s): %.2f M wedge updates/s wall, %.2f M per CPU-second%s\n", threads,
                  per_s / 1e6, cpu * double(ne) / 1e6,
                  threads == 1 ? "" : (" (wall speed-up " + std::to_string(per_s / r1).substr(0, 4) + ")").c_str());
    }
    // Whole steps of the solver (kernel + gather by node + constraints + velocity/position update).
    m.bcs.push_back({"zmin", 2, solve::BcKind::fixed, {}});
    m.control.end_time = 1e9;
    double s1 = 0;
    for (int threads : {1, 2}) {
      omp_set_num_threads(threads);
      solve::Solver s(m);
      solve::SolverState st = s.state();
      st.x = x;
      s.set_state(st);
      double cpu = 0;
      const double steps = rate([&] { s.step(); }, min_s, &cpu);
      const double per_s = steps * double(ne);
      if (threads == 1) s1 = per_s;
      std::printf("full solver step, %d thread(s): %.2f M wedge updates/s wall (%.1f ms/step), %.2f M per CPU-second%s\n",
                  threads, per_s / 1e6, 1e3 / steps, cpu * double(ne) / 1e6,
                  threads == 1 ? "" : (" (speed-up " + std::to_string(per_s / s1).substr(0, 4) + ")").c_str());
    }
    return 0;
  });
}
