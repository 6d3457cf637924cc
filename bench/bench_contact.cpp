// Benchmark of the penalty contact (issue 5, speed): contact search + force for 20,000 slave
// nodes against a 40,000-triangle master surface, time per step with 1 and 2 threads.
//
// Master: a wavy 100×200-cell surface (40,000 triangles, 1 mm cells) like a patch of skin;
// slaves: 20,000 nodes scattered over it, 60 % penetrating by up to 0.3 mm. Two regimes:
//   "steady": the master drifts slowly (search grid re-used, the usual case),
//   "rebuild": the master moves by more than the search margin every step (grid re-built).
// Then segment-to-surface: the slaves are a 143×143-node lattice surface (20,449 nodes, 40,328
// facets, 9 contact points each), the cost of integrating over slave facets.
// Wall-clock time depends on the machine's load; the process CPU time is printed beside it
// (for 2 threads it is the sum over both).
// Sample run: bench_contact            (prints ms per step; no arguments)
#include <array>
#include <chrono>
#include <ctime>
#include <utility>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <random>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "pipeline/cli.h"
#include "solve/contact.h"
#include "solve/make_block.h"

namespace {

double cpu_ms() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e3 * double(ts.tv_sec) + 1e-6 * double(ts.tv_nsec);
}

/// Wall-clock and process CPU time per step [ms].
std::pair<double, double> time_steps(solve::ContactPair& pair, std::vector<double>& x, const std::vector<double>& v,
                  const std::vector<double>& mass, std::vector<double>& f, int n_master_nodes,
                  double shift_per_step, int steps) {
  const double dt = 1e-3;
  pair.add_forces(x.data(), v.data(), mass.data(), dt, f.data());  // warm-up: first build
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = cpu_ms();
  for (int s = 0; s < steps; ++s) {
    const double shift = s % 2 ? -shift_per_step : shift_per_step;  // back and forth
    for (int i = 0; i < n_master_nodes; ++i) x[3 * std::size_t(i) + 2] += shift;
    pair.add_forces(x.data(), v.data(), mass.data(), dt, f.data());
  }
  const auto t1 = std::chrono::steady_clock::now();
  return {std::chrono::duration<double, std::milli>(t1 - t0).count() / steps, (cpu_ms() - c0) / steps};
}

/// A flat tri3 lattice of nx × ny cells over [0, size_x] × [0, size_y] (make_plate's grid: node
/// (i, j) = i + (nx+1)·j, triangles {a, b, c}, {a, c, d} facing +z), its nodes appended to x and
/// its triangles, numbered as the appended nodes, returned.
std::vector<std::array<int, 3>> append_lattice(int nx, int ny, double size_x, double size_y, std::vector<double>& x) {
  solve::PlateSpec ps;
  ps.type = solve::ElementType::tri3;
  ps.nx = nx;
  ps.ny = ny;
  ps.size = {size_x, size_y};
  const solve::Model plate = solve::make_plate(ps, {"lattice", 1e-3, 1, 0.3, false});
  const int first_node = int(x.size() / 3);
  x.insert(x.end(), plate.X.begin(), plate.X.end());
  std::vector<std::array<int, 3>> tris = plate.surfaces.at("plate");
  for (auto& t : tris)
    for (int& id : t) id += first_node;
  return tris;
}

/// Runs body(threads) with 1, then 2 OpenMP threads.
template <class Body>
void on_1_and_2_threads(Body&& body) {
  for (int threads : {1, 2}) {
#ifdef _OPENMP
    omp_set_num_threads(threads);
#else
    if (threads > 1) break;
#endif
    body(threads);
  }
}

}  // namespace

int main(int argc, char** argv) {
  pipeline::Cli cli("bench_contact", "Contact search and forces: 20,000 slave nodes over a 40,000-triangle wavy master "
                                     "surface, on 1 and 2 threads. No options.");
  return pipeline::run_main(cli, argc, argv, [&] {
    const int nx = 100, ny = 200, ns = 20000;
    std::vector<double> x;
    solve::ContactSpec spec;
    spec.name = "bench";
    auto height = [](double px, double py) { return 4 * std::sin(0.1 * px) * std::cos(0.07 * py); };
    spec.master_tris = append_lattice(nx, ny, nx, ny, x);  // 1 mm cells
    const int nm = int(x.size() / 3);
    for (std::size_t i = 0; i < x.size(); i += 3) x[i + 2] = height(x[i], x[i + 1]);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(0, 1);
    for (int j = 0; j < ns; ++j) {
      const double px = nx * u(rng), py = ny * u(rng);
      x.insert(x.end(), {px, py, height(px, py) + 0.5 * (u(rng) - 0.6)});
      spec.slave_nodes.push_back(nm + j);
    }
    const std::size_t nn = std::size_t(nm + ns);
    std::vector<double> v(3 * nn, 0.0), f(3 * nn, 0.0), mass(nn, 1e-3);
    std::printf("contact search + force: %d slave nodes, %zu master triangles\n", ns, spec.master_tris.size());
    on_1_and_2_threads([&](int threads) {
      for (const bool rebuild : {false, true}) {
        std::vector<double> xs = x;
        solve::ContactPair pair(spec, nn);
        // Margin is a quarter of the mean edge (~0.3 mm): ±1e-4 mm/step re-uses the grid, ±0.7 mm re-builds.
        const auto [wall, cpu] = time_steps(pair, xs, v, mass, f, nm, rebuild ? 0.7 : 1e-4, 100);
        std::printf("  threads %d, %-8s grid: %.2f ms/step wall, %.2f ms/step CPU (max penetration %.3f mm, "
                    "resultant %.1f N)\n", threads, rebuild ? "rebuilt" : "re-used", wall, cpu, pair.max_penetration(),
                    pair.resultant_force()[2]);
      }
    });
    // Segment-to-surface: the same master, a 142 × 142-cell slave surface lattice over it, its
    // facets turned to face the master (−z), its nodes up to 0.3 mm into it as the node slaves.
    std::vector<double> xf(x.begin(), x.begin() + 3 * std::ptrdiff_t(nm));
    solve::ContactSpec seg = spec;
    seg.slave_nodes.clear();
    for (const auto& t : append_lattice(142, 142, nx, ny, xf)) seg.slave_tris.push_back({t[0], t[2], t[1]});
    for (std::size_t i = 3 * std::size_t(nm); i < xf.size(); i += 3) {
      seg.slave_nodes.push_back(int(i / 3));
      xf[i + 2] = height(xf[i], xf[i + 1]) + 0.5 * (u(rng) - 0.6);
    }
    const std::size_t nf = xf.size() / 3;
    std::vector<double> vf(3 * nf, 0.0), ff(3 * nf, 0.0), massf(nf, 1e-3);
    std::printf("segment-to-surface: %zu slave nodes, %zu slave facets, %zu master triangles\n", seg.slave_nodes.size(),
                seg.slave_tris.size(), seg.master_tris.size());
    on_1_and_2_threads([&](int threads) {
      std::vector<double> xs = xf;
      solve::ContactPair pair(seg, nf);
      const auto [wall, cpu] = time_steps(pair, xs, vf, massf, ff, nm, 1e-4, 10);
      std::printf("  threads %d, %zu contact points, re-used grid: %.2f ms/step wall, %.2f ms/step CPU (max penetration "
                  "%.3f mm, resultant %.1f N)\n", threads, pair.n_points(), wall, cpu, pair.max_penetration(),
                  pair.resultant_force()[2]);
    });
    return 0;
  });
}
