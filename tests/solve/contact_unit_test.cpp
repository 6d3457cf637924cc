// Unit tests of the penalty contact: geometry kernels, search, forces, pressure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "pipeline/error.h"
#include "solve/contact.h"
#include "solve/internal/contact_geometry.h"
#include "solve/make_block.h"

using solve::ContactPair;
using solve::ContactSpec;
using solve::internal::BoxGrid;
using solve::internal::closest_point_on_triangle;
using solve::internal::Feature;

namespace {

/// A flat square master z = 0 of n×n cells of side h from (0, 0), each split into two
/// triangles with outward normal +z. Nodes 0 … (n+1)²−1.
struct FlatMaster {
  int n;
  double h;
  std::vector<double> x;
  std::vector<std::array<int, 3>> tris;
  FlatMaster(int n_, double h_) : n(n_), h(h_) {
    // make_plate's tri3 surface: node (i, j) = i + (n+1)·j, cell → {a, b, c}, {a, c, d}.
    solve::PlateSpec ps;
    ps.type = solve::ElementType::tri3;
    ps.nx = n;
    ps.ny = n;
    ps.size = {n * h, n * h};
    const solve::Model plate = solve::make_plate(ps, {"master", 1e-3, 1, 0.3, false});
    x = plate.X;
    tris = plate.surfaces.at("plate");
  }
  int nodes() const { return (n + 1) * (n + 1); }
  /// Lumped tributary area of each node: 1/3 of its triangles' areas [mm²].
  std::vector<double> tributary() const {
    std::vector<double> a(std::size_t(nodes()), 0.0);
    for (const auto& t : tris)
      for (int id : t) a[std::size_t(id)] += h * h / 2 / 3;
    return a;
  }
};

/// One slave node (the last node) at p over the flat master, its mass slave_mass, the master
/// nodes massless (kinematic); the spec is ready for the test to adjust before making the pair.
struct OneSlave {
  std::vector<double> x, v, f, mass;
  ContactSpec spec;
  std::size_t s;  // the slave's node index
  OneSlave(const FlatMaster& m, std::array<double, 3> p, double slave_mass, const std::string& name)
      : x(m.x), s(std::size_t(m.nodes())) {
    x.insert(x.end(), p.begin(), p.end());
    v.assign(x.size(), 0.0);
    f.assign(x.size(), 0.0);
    mass.assign(s + 1, 0.0);
    mass[s] = slave_mass;
    spec.name = name;
    spec.slave_nodes = {int(s)};
    spec.master_tris = m.tris;
  }
  void add_forces(ContactPair& pair, double dt) { pair.add_forces(x.data(), v.data(), mass.data(), dt, f.data()); }
};

/// Contact force on one slave at p over the flat master (masters massless = kinematic).
std::array<double, 3> force_on_slave(const FlatMaster& m, std::array<double, 3> p, double slave_mass,
                                     double dt, double* max_pen = nullptr) {
  OneSlave c(m, p, slave_mass, "flat");
  ContactPair pair(c.spec, c.mass.size());
  c.add_forces(pair, dt);
  if (max_pen) *max_pen = pair.max_penetration();
  // Action and reaction: the master nodes carry minus the slave force.
  double sum[3] = {0, 0, 0};
  for (std::size_t i = 0; i < c.f.size(); ++i) sum[i % 3] += c.f[i];
  for (double sc : sum) EXPECT_NEAR(sc, 0.0, 1e-12);
  return {c.f[3 * c.s], c.f[3 * c.s + 1], c.f[3 * c.s + 2]};
}

}  // namespace

TEST(closest_point_on_triangle, finds_face_edge_and_vertex_regions) {
  const double a[3] = {0, 0, 0}, b[3] = {2, 0, 0}, c[3] = {0, 2, 0};
  const double above[3] = {0.5, 0.5, 1};
  auto r = closest_point_on_triangle(above, a, b, c);
  EXPECT_EQ(r.feature, Feature::face);
  EXPECT_NEAR(r.dist2, 1.0, 1e-14);
  EXPECT_NEAR(r.weight[1], 0.25, 1e-14);
  const double beyond_ab[3] = {1, -1, 0};
  r = closest_point_on_triangle(beyond_ab, a, b, c);
  EXPECT_EQ(r.feature, Feature::edge0);
  EXPECT_NEAR(r.weight[0], 0.5, 1e-14);
  const double beyond_bc[3] = {2, 2, -1};
  r = closest_point_on_triangle(beyond_bc, a, b, c);
  EXPECT_EQ(r.feature, Feature::edge1);
  const double beyond_c[3] = {-1, 3, 0};
  r = closest_point_on_triangle(beyond_c, a, b, c);
  EXPECT_EQ(r.feature, Feature::vertex2);
  EXPECT_NEAR(r.dist2, 2.0, 1e-14);
}

TEST(closest_point_on_triangle, matches_dense_sampling_on_random_triangles) {
  // The closest point must be no farther than any of 2,000 sampled points of the triangle
  // (sampling is exact up to round-off when it hits the minimizer; 1e-12 relative slack).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    double a[3], b[3], c[3], p[3];
    for (int k = 0; k < 3; ++k) a[k] = u(rng), b[k] = u(rng), c[k] = u(rng), p[k] = 2 * u(rng);
    const auto r = closest_point_on_triangle(p, a, b, c);
    double w_sum = r.weight[0] + r.weight[1] + r.weight[2];
    EXPECT_NEAR(w_sum, 1.0, 1e-12);
    for (int i = 0; i < 2000; ++i) {
      double s = 0.5 * (u(rng) + 1), t = 0.5 * (u(rng) + 1);
      if (s + t > 1) s = 1 - s, t = 1 - t;
      double d2 = 0;
      for (int k = 0; k < 3; ++k) {
        const double q = a[k] + s * (b[k] - a[k]) + t * (c[k] - a[k]);
        d2 += (p[k] - q) * (p[k] - q);
      }
      ASSERT_LE(r.dist2, d2 * (1 + 1e-12) + 1e-15);
    }
  }
}

TEST(box_grid, search_equals_brute_force_on_random_boxes) {
  // Every box containing a query point must be listed in the point's cell: exact set equality
  // after the containment filter, so no tolerance.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(0, 100), size(0.1, 6);
  std::vector<std::array<double, 6>> boxes(5000);
  for (auto& b : boxes)
    for (int k = 0; k < 3; ++k) {
      b[std::size_t(k)] = pos(rng);
      b[std::size_t(k) + 3] = b[std::size_t(k)] + size(rng);
    }
  BoxGrid grid;
  grid.build(boxes);
  auto inside = [](const std::array<double, 6>& b, const double* p) {
    return p[0] >= b[0] && p[0] <= b[3] && p[1] >= b[1] && p[1] <= b[4] && p[2] >= b[2] && p[2] <= b[5];
  };
  std::uniform_real_distribution<double> q(-5, 110);
  for (int trial = 0; trial < 5000; ++trial) {
    const double p[3] = {q(rng), q(rng), q(rng)};
    std::vector<int> brute, found;
    for (std::size_t i = 0; i < boxes.size(); ++i)
      if (inside(boxes[i], p)) brute.push_back(int(i));
    const long cell = grid.cell_of(p);
    if (cell >= 0)
      for (const int* it = grid.begin(cell); it != grid.end(cell); ++it)
        if (inside(boxes[std::size_t(*it)], p)) found.push_back(*it);
    ASSERT_EQ(found, brute) << "query " << trial;
  }
}

namespace {
/// A wavy, jittered 40×40-cell triangulated surface with 3,000 random slaves near it, 60 % of
/// them below it; slave mass 1e-3 g, kinematic master, Δt = 1e-3 ms.
struct RandomCase {
  FlatMaster m{40, 1.0};
  std::vector<double> x, v, mass;
  ContactSpec spec;
  int nm = 0, ns = 3000;
  double dt = 1e-3;
  explicit RandomCase(int n_slaves = 3000) : ns(n_slaves) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> jit(-0.2, 0.2), u(0, 1);
    for (std::size_t i = 0; i < m.x.size(); i += 3) {
      m.x[i] += jit(rng);
      m.x[i + 1] += jit(rng);
      m.x[i + 2] = 3 * std::sin(0.2 * m.x[i]) * std::cos(0.15 * m.x[i + 1]);
    }
    nm = m.nodes();
    x = m.x;
    for (int j = 0; j < ns; ++j) {
      const double px = 2 + 36 * u(rng), py = 2 + 36 * u(rng);
      const double pz = 3 * std::sin(0.2 * px) * std::cos(0.15 * py) + (u(rng) - 0.6) * 0.8;
      x.insert(x.end(), {px, py, pz});
    }
    const std::size_t nn = std::size_t(nm + ns);
    v.assign(3 * nn, 0.0);
    mass.assign(nn, 0.0);
    spec.name = "random";
    spec.master_tris = m.tris;
    for (int j = 0; j < ns; ++j) {
      spec.slave_nodes.push_back(nm + j);
      mass[std::size_t(nm + j)] = 1e-3;
    }
  }
  std::vector<double> forces() const {
    std::vector<double> f(x.size(), 0.0);
    ContactPair pair(spec, mass.size());
    pair.add_forces(x.data(), v.data(), mass.data(), dt, f.data());
    return f;
  }
};
}  // namespace

TEST(contact_pair, search_equals_brute_force_on_a_random_surface) {
  // The force on each slave must equal the brute-force one (nearest of all triangles by the
  // same kernel, penetration = distance, force along closest point − slave, k = s·m/Δt²), to
  // round-off (1e-9 relative).
  const RandomCase rc;
  const auto f = rc.forces();
  const double k = 0.1 * 1e-3 / (rc.dt * rc.dt);
  int in_contact = 0;
  for (int j = 0; j < rc.ns; ++j) {
    const double* p = &rc.x[3 * std::size_t(rc.nm + j)];
    double best = 1e300;
    std::array<double, 3> c{};
    for (const auto& t : rc.m.tris) {
      const auto r = closest_point_on_triangle(p, &rc.x[3 * std::size_t(t[0])], &rc.x[3 * std::size_t(t[1])],
                                               &rc.x[3 * std::size_t(t[2])]);
      if (r.dist2 < best) best = r.dist2, c = r.point;
    }
    const double* fs = &f[3 * std::size_t(rc.nm + j)];
    const double fmag = std::sqrt(fs[0] * fs[0] + fs[1] * fs[1] + fs[2] * fs[2]);
    // The surface is a height field (the jitter keeps every triangle's xy projection positive):
    // below it ⇔ below its height at the slave's (x, y).
    double surface_z = 0;
    for (const auto& t : rc.m.tris) {
      const double* a = &rc.x[3 * std::size_t(t[0])];
      const double* b = &rc.x[3 * std::size_t(t[1])];
      const double* cc = &rc.x[3 * std::size_t(t[2])];
      const double det = (b[0] - a[0]) * (cc[1] - a[1]) - (cc[0] - a[0]) * (b[1] - a[1]);
      const double l1 = ((p[0] - a[0]) * (cc[1] - a[1]) - (cc[0] - a[0]) * (p[1] - a[1])) / det;
      const double l2 = ((b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1])) / det;
      if (l1 >= 0 && l2 >= 0 && l1 + l2 <= 1) {
        surface_z = a[2] + l1 * (b[2] - a[2]) + l2 * (cc[2] - a[2]);
        break;
      }
    }
    const bool below = p[2] < surface_z;
    if (!below) {
      EXPECT_EQ(fmag, 0.0) << "slave " << j;
      continue;
    }
    ++in_contact;
    EXPECT_NEAR(fmag, k * std::sqrt(best), 1e-9 * k * std::sqrt(best)) << "slave " << j;
    for (int q = 0; q < 3; ++q) EXPECT_NEAR(fs[q] / fmag, (c[std::size_t(q)] - p[q]) / std::sqrt(best), 1e-9);
  }
  EXPECT_GT(in_contact, rc.ns / 2);  // 60 % of the slaves were placed below
}

TEST(contact_pair, results_do_not_depend_on_the_thread_count) {
  // Per-slave work in parallel, serial gather in slave order: bitwise equal forces. 20,000
  // slaves: above kMinParallel, so the loop does run on 2 threads.
  const RandomCase rc(20000);
#ifdef _OPENMP
  omp_set_num_threads(1);
  const auto f1 = rc.forces();
  omp_set_num_threads(2);
  const auto f2 = rc.forces();
  EXPECT_EQ(f1, f2);
#else
  GTEST_SKIP() << "built without OpenMP";
#endif
}

TEST(contact_pair, penetrating_node_gets_k_times_gap_along_the_normal) {
  // Exact to round-off: k = s·m/Δt² with a kinematic (massless) master, gap 0.01 mm.
  const FlatMaster m(4, 1.0);
  const double mass = 2e-3, dt = 5e-3, gap = 0.01, k = 0.1 * mass / (dt * dt);
  const auto f = force_on_slave(m, {1.3, 2.6, -gap}, mass, dt);
  EXPECT_NEAR(f[0], 0.0, 1e-12);
  EXPECT_NEAR(f[1], 0.0, 1e-12);
  EXPECT_NEAR(f[2], k * gap, 1e-9 * k * gap);
  const auto free = force_on_slave(m, {1.3, 2.6, +gap}, mass, dt);
  EXPECT_EQ(free[2], 0.0);
  // Deep, 0.8 mm: 0.7 of the master's mean edge (1.14 mm), within the search depth of one mean
  // edge (contact.cpp). A depth halved dropped such a slave without force or warning (sweep N).
  const auto deep = force_on_slave(m, {1.3, 2.6, -0.8}, mass, dt);
  EXPECT_NEAR(deep[2], k * 0.8, 1e-9 * k * 0.8);
}

// The search grid follows the master: moved 5 edge lengths onto a slave it was far from when the
// grid was built, the master finds it and pushes it out with k·gap. A grid never re-built passed
// every fast test (only the slow Hertz test saw it: sweep L).
TEST(contact_pair, the_search_follows_a_master_that_moved) {
  const FlatMaster m(4, 1.0);
  const double mass = 2e-3, dt = 5e-3, gap = 0.01, k = 0.1 * mass / (dt * dt);
  OneSlave c(m, {1.3, 2.6, 5.0}, mass, "moving");
  ContactPair pair(c.spec, c.mass.size());
  c.add_forces(pair, dt);
  EXPECT_EQ(c.f[3 * c.s + 2], 0.0);
  for (int i = 0; i < m.nodes(); ++i) c.x[3 * std::size_t(i) + 2] += 5.0 + gap;
  std::fill(c.f.begin(), c.f.end(), 0.0);
  c.add_forces(pair, dt);
  EXPECT_NEAR(c.f[3 * c.s + 2], k * gap, 1e-9 * k * gap);
}

TEST(contact_pair, edge_and_vertex_projections_get_contact) {
  // Slaves exactly above an interior edge, a diagonal, an interior vertex, a boundary edge and a
  // boundary corner of the flat master must all get the full k·gap (no gap between facets).
  const FlatMaster m(4, 1.0);
  const double mass = 1e-3, dt = 1e-2, gap = 0.02, k = 0.1 * mass / (dt * dt);
  for (auto xy : std::vector<std::array<double, 2>>{{1.5, 2.0}, {1.5, 1.5}, {2, 2}, {0, 1.5}, {4, 4}, {0, 0}}) {
    double pen = 0;
    const auto f = force_on_slave(m, {xy[0], xy[1], -gap}, mass, dt, &pen);
    EXPECT_NEAR(f[2], k * gap, 1e-9 * k * gap) << xy[0] << ", " << xy[1];
    EXPECT_NEAR(pen, gap, 1e-12);
  }
  // Beyond the master's free edge (x = 4): within 0.1 of a mean edge (1.14 mm) still pushed, 0.3 mm
  // beyond not (a tolerance of half an edge pushed it and passed every test: sweep N).
  EXPECT_NEAR(force_on_slave(m, {4.05, 2.0, -gap}, mass, dt)[2], k * gap, 1e-9 * k * gap);
  EXPECT_EQ(force_on_slave(m, {4.3, 2.0, -gap}, mass, dt)[2], 0.0);
  // A node in a concave valley (two facets at 90°) whose closest point is the valley edge is
  // pushed toward the edge.
  ContactSpec spec;
  spec.name = "valley";
  // Facets y = 0 (z ≤ 0 … ) and z = 0 meeting at the x axis; normals +y and +z (into the valley).
  std::vector<double> x = {0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0, 0, 0, 2, 2, 0, 2};
  spec.master_tris = {{0, 1, 2}, {0, 2, 3}, {0, 4, 5}, {0, 5, 1}};
  x.insert(x.end(), {1.0, -0.01, -0.02});  // below both facets, near the valley edge
  spec.slave_nodes = {6};
  std::vector<double> v(x.size(), 0.0), f(x.size(), 0.0), mass_v(7, 0.0);
  mass_v[6] = mass;
  ContactPair pair(spec, 7);
  pair.add_forces(x.data(), v.data(), mass_v.data(), dt, f.data());
  const double d = std::sqrt(0.01 * 0.01 + 0.02 * 0.02);
  EXPECT_NEAR(f[18], 0.0, 1e-12);
  EXPECT_NEAR(f[19], k * 0.01, 1e-9);
  EXPECT_NEAR(f[20], k * 0.02, 1e-9);
  EXPECT_NEAR(pair.max_penetration(), d, 1e-12);
}

TEST(contact_pair, uniform_load_on_a_flat_master_gives_load_over_area) {
  // Case 1, matching: slaves on the master vertices with masses ∝ the master nodes' tributary
  // areas, all at the same gap: every master node, boundary included, shows load/area to
  // round-off (k ∝ slave mass makes the penalty a uniform surface stiffness).
  const FlatMaster m(6, 1.0);
  const double dt = 1e-2, gap = 0.01, rho_a = 1e-3;  // slave mass per area [g/mm²]
  const std::vector<double> trib = m.tributary();
  // Slaves on a (ns_side+1)² lattice over the master; with ns_side = n they sit on the master
  // vertices and get masses ∝ the master tributary areas, else ∝ their own lattice areas.
  auto run = [&](int ns_side, double& total_load, bool with_slave_tris = false) {
    std::vector<double> x = m.x;
    const int nm = m.nodes();
    ContactSpec spec;
    spec.name = "uniform";
    spec.master_tris = m.tris;
    std::vector<double> mass(std::size_t(nm), 0.0);
    const double hs = m.n * m.h / ns_side;
    for (int j = 0; j <= ns_side; ++j)
      for (int i = 0; i <= ns_side; ++i) {
        x.insert(x.end(), {i * hs, j * hs, -gap});
        spec.slave_nodes.push_back(int(mass.size()));
        const double wx = (i == 0 || i == ns_side) ? 0.5 : 1, wy = (j == 0 || j == ns_side) ? 0.5 : 1;
        mass.push_back(rho_a * (ns_side == m.n ? trib[std::size_t(j * (m.n + 1) + i)] : hs * hs * wx * wy));
      }
    if (with_slave_tris)
      for (int j = 0; j < ns_side; ++j)
        for (int i = 0; i < ns_side; ++i) {
          const int a = nm + j * (ns_side + 1) + i, b = a + 1, c = a + ns_side + 2, d = a + ns_side + 1;
          spec.slave_tris.push_back({a, c, b});
          spec.slave_tris.push_back({a, d, c});
        }
    std::vector<double> v(x.size(), 0.0), f(x.size(), 0.0);
    ContactPair pair(spec, mass.size());
    pair.add_forces(x.data(), v.data(), mass.data(), dt, f.data());
    total_load = pair.resultant_force()[2];
    return std::vector<double>(pair.pressure().begin(), pair.pressure().begin() + nm);
  };
  double load = 0;
  const double area = (m.n * m.h) * (m.n * m.h);
  const auto p_match = run(m.n, load);
  for (double p : p_match) EXPECT_NEAR(p, load / area, 1e-12 * load / area);
  // Case 2, non-matching with an integer ratio (slaves 3× denser): the slave lattice integrates
  // each master hat function exactly, so again round-off (1e-12).
  // The 4 corners are skipped here and below: a corner's lumped area (1/3 of its one or two
  // facets: 1/6 or 1/3 of a cell) is not its quarter cell, which the slave lattice masses follow.
  auto corner = [&](std::size_t id) {
    const int i = int(id) % (m.n + 1), j = int(id) / (m.n + 1);
    return (i == 0 || i == m.n) && (j == 0 || j == m.n);
  };
  const auto p_three = run(18, load);
  for (std::size_t i = 0; i < p_three.size(); ++i)
    if (!corner(i)) { EXPECT_NEAR(p_three[i], load / area, 1e-12 * load / area); }
  // Case 3, non-matching, slaves 2.5× denser: force over master tributary area aliases (±12 %);
  // with slave facets the pressure is force over gathered slave area: exact (1e-12).
  const auto p_fine = run(15, load, true);
  for (std::size_t i = 0; i < p_fine.size(); ++i)
    if (!corner(i)) { EXPECT_NEAR(p_fine[i], load / area, 1e-12 * load / area); }
  // And force × master tributary area still adds up to the load.
  const auto p_plain = run(15, load);
  double sum = 0;
  for (int j = 0; j <= m.n; ++j)
    for (int i = 0; i <= m.n; ++i) {
      const double a = trib[std::size_t(j * (m.n + 1) + i)];
      sum += p_plain[std::size_t(j * (m.n + 1) + i)] * a;
    }
  EXPECT_NEAR(sum, load, 1e-12 * load);  // pressure × tributary area adds up to the load
}

// Segment-to-surface: slave facets on a lattice offset from the master's (spacing 2 vs 2.5 mm,
// the patch test's ratio), all at the same gap over a flat kinematic master. The master must
// receive the consistent nodal loads of the uniform pressure, p·h² on interior nodes; node-to-
// surface (the same slaves without facets) aliases them. Measured: segments 0.42 %, nodes 10.4 %.
TEST(contact_pair, slave_facets_give_the_master_consistent_nodal_loads) {
  const FlatMaster m(4, 2.5);
  const int nm = m.nodes(), ns_side = 5;
  const double hs = 2.0, gap = 0.01, rho_a = 1e-3, dt = 1e-2;
  auto master_loads = [&](bool facets, double& pressure) {
    std::vector<double> x = m.x, mass(std::size_t(nm), 0.0);
    ContactSpec spec;
    spec.name = facets ? "segments" : "nodes";
    spec.master_tris = m.tris;
    // The slave lattice: make_plate's grid at z = −gap (node (i, j) = nm + i + (ns_side+1)·j),
    // its triangles turned to face the master (−z); lumped masses ρ_a × tributary area.
    solve::PlateSpec ps;
    ps.type = solve::ElementType::tri3;
    ps.nx = ns_side;
    ps.ny = ns_side;
    ps.size = {ns_side * hs, ns_side * hs};
    ps.origin = {0, 0, -gap};
    const solve::Model slave = solve::make_plate(ps, {"slave", 1e-3, 1, 0.3, false});
    x.insert(x.end(), slave.X.begin(), slave.X.end());
    for (int j = 0; j <= ns_side; ++j)
      for (int i = 0; i <= ns_side; ++i) {
        spec.slave_nodes.push_back(int(mass.size()));
        const double wx = (i == 0 || i == ns_side) ? 0.5 : 1, wy = (j == 0 || j == ns_side) ? 0.5 : 1;
        mass.push_back(rho_a * hs * hs * wx * wy);
      }
    if (facets)
      for (auto t : slave.surfaces.at("plate"))
        spec.slave_tris.push_back({nm + t[0], nm + t[2], nm + t[1]});
    std::vector<double> v(x.size(), 0.0), f(x.size(), 0.0);
    ContactPair pair(spec, mass.size());
    if (facets) { EXPECT_EQ(pair.n_points(), std::size_t(9 * 2 * ns_side * ns_side)); }
    pair.add_forces(x.data(), v.data(), mass.data(), dt, f.data());
    pressure = pair.resultant_force()[2] / 100.0;
    EXPECT_NEAR(pressure, 0.1 * rho_a * gap / (dt * dt), 1e-9 * pressure);  // k per area = s·ρ_a/Δt²
    double worst = 0;
    for (int j = 1; j < m.n; ++j)
      for (int i = 1; i < m.n; ++i)
        worst = std::max(worst, std::fabs(-f[3 * std::size_t(j * (m.n + 1) + i) + 2] / (pressure * 2.5 * 2.5) - 1));
    return worst;
  };
  double p_seg = 0, p_nodes = 0;
  const double seg = master_loads(true, p_seg), nodes = master_loads(false, p_nodes);
  std::printf("interior master loads vs p·h²: segments %.2f %%, nodes %.2f %%\n", 100 * seg, 100 * nodes);
  EXPECT_LT(seg, 0.01);
  EXPECT_GT(nodes, 0.05);  // what the segments are for
}

TEST(contact_pair, two_sided_pushes_back_to_the_side_it_came_from) {
  // Thin shell: a slave approaching from below (side −) and penetrating upward gets pushed down.
  const FlatMaster m(4, 1.0);
  OneSlave c(m, {2.3, 1.7, -0.05}, 1e-3, "shell");
  c.spec.two_sided = true;
  ContactPair pair(c.spec, c.mass.size());
  c.add_forces(pair, 1e-2);
  EXPECT_EQ(c.f[3 * c.s + 2], 0.0);  // below, not penetrating: free
  c.x[3 * c.s + 2] = +0.01;          // crossed the shell by 0.01 mm
  c.add_forces(pair, 1e-2);
  EXPECT_NEAR(c.f[3 * c.s + 2], -0.1 * 1e-3 / 1e-4 * 0.01, 1e-12);
}

TEST(contact_pair, friction_sticks_below_and_slides_at_the_coulomb_limit) {
  // Elastic-slip friction: a small tangential slip gives a spring force k·slip; a large one is
  // capped at μ·F_n (exact by construction, round-off tolerance).
  const FlatMaster m(4, 1.0);
  OneSlave c(m, {2.3, 1.7, -0.01}, 1e-3, "friction");
  c.spec.friction = 0.5;
  const double dt = 1e-2, k = 0.1 * 1e-3 / (dt * dt), fn = k * 0.01;
  ContactPair pair(c.spec, c.mass.size());
  c.v[3 * c.s] = 0.1;  // slips 0.001 mm per step along x: k·0.001 = 0.1·fn < μ·fn
  c.add_forces(pair, dt);
  EXPECT_NEAR(c.f[3 * c.s], -k * 0.001, 1e-12);
  EXPECT_NEAR(pair.resultant_force()[2], fn, 1e-12);
  c.v[3 * c.s] = 10;  // slips 0.1 mm: limited to μ·fn
  c.add_forces(pair, dt);
  EXPECT_NEAR(pair.resultant_force()[0], -0.5 * fn, 1e-12);
  double shear = 0;
  for (double t : pair.shear()) shear += t;
  EXPECT_GT(shear, 0.0);
}

TEST(contact_pair, rejects_out_of_range_nodes) {
  ContactSpec spec;
  spec.name = "bad";
  spec.master_tris = {{0, 1, 2}};
  spec.slave_nodes = {5};
  EXPECT_THROW(ContactPair(spec, 4), pipeline::Error);
  spec.slave_nodes = {3};
  spec.penalty_scale = 2;
  EXPECT_THROW(ContactPair(spec, 4), pipeline::Error);
}
