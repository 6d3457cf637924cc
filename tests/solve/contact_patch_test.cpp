// Contact patch test: two blocks with non-matching meshes pressed together must transmit a
// uniform pressure. Lower block (master surface, its top) 10 × 5 × 10 mm with 4 × 2 × 4 hex cells;
// upper block (slave nodes, its bottom) with 5 × 2 × 5 cells, so the slave spacing is 1.25× the
// master's — the worst kind of non-matching for node-to-surface (no slave lattice point repeats
// within a master cell). Both blocks E = 0.6 MPa, ν = 0.45 (same ν: no interface shear),
// frictionless, symmetry planes x = 0 and z = 0, lower base held in y, upper top pushed down by
// 0.1 mm: a uniform uniaxial stress σ = E·ε, ε = δ/(10 mm + penalty gap).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "solve/make_block.h"
#include "solve/solver.h"

// KNOWN FAILURE, disabled (see the report of issue 5): one-pass node-to-surface contact does not
// pass this patch test. Measured (static by t = 12 ms; same at 30 ms), deviation from the mean
// 0.00421 MPa: with the plain pressure rule (force / master tributary area, what the solver uses
// today) interior nodes ±8 %, interface corners up to +65 %; with ContactSpec::slave_tris filled
// (force / gathered slave area, requested from solver-core) interior ±3.5 %, corners −25 %/+17 %
// (a corner's lumped 1/3-of-facets area is not the quarter cell its hexahedral force stands for).
// The interior residue is physical: the master nodal loads alias, the master surface waves, the
// slave forces follow. Remedies not done yet: two-pass (symmetric) contact, mortar projection.
TEST(contact_patch, DISABLED_non_matching_blocks_transmit_uniform_pressure) {
  solve::Material mat{"soft", 1e-3, 0.6, 0.45, false};
  solve::BlockSpec lower;
  lower.nx = 4, lower.ny = 2, lower.nz = 4;
  lower.size = {10, 5, 10};
  lower.origin = {0, -5, 0};
  solve::BlockSpec upper = lower;
  upper.nx = 5, upper.nz = 5;
  upper.origin = {0, 0, 0};
  solve::Model m = solve::make_block(lower, mat);
  solve::append_model(m, solve::make_block(upper, mat), "up_");
  using solve::BcKind;
  const double delta = 0.1, t_load = 6, t_end = 12;
  m.bcs.push_back({"ymin", 1, BcKind::fixed, {}});
  for (const char* g : {"xmin", "up_xmin"}) m.bcs.push_back({g, 0, BcKind::fixed, {}});
  for (const char* g : {"zmin", "up_zmin"}) m.bcs.push_back({g, 2, BcKind::fixed, {}});
  m.bcs.push_back({"up_ymax", 1, BcKind::displacement, solve::Curve{{0, t_load, t_end}, {0, -delta, -delta}}});
  solve::ContactDef c;
  c.name = "blocks";
  c.slave = "up_ymin";
  c.master = "ymax";
  c.damping_ratio = 0.2;
  m.contacts.push_back(c);
  m.control.end_time = t_end;
  m.control.damping_alpha = 2.0;
  solve::Solver s(m);
  s.run_until(t_end);
  ASSERT_EQ(s.health(), "");
  // The transmitted mean pressure is the contact force over the area; every master node of the
  // interface must show it within 2 % (the tolerance). The reference is the measured
  // mean; the mean itself is E·(δ − penalty gap)/10 within 5 % (the gap is ~30 % of δ here).
  const double mean = s.contacts()[0].resultant_force()[1] / 100.0;  // on the slave: +y
  const double sigma = 0.6 * (delta - s.max_penetration()) / 10;  // the penalty gap takes a share
  EXPECT_NEAR(mean, sigma, 0.05 * sigma);
  const auto p = s.contact_pressure();
  double worst = 0;
  for (int id : s.model().group("ymax")) {
    EXPECT_NEAR(p[std::size_t(id)], mean, 0.02 * mean) << "master node " << id << " at x " << s.x()[3 * std::size_t(id)] << " z " << s.x()[3 * std::size_t(id) + 2];
    worst = std::max(worst, std::fabs(p[std::size_t(id)] / mean - 1));
  }
  std::printf("patch: mean pressure %.5f MPa (E·ε = %.5f), worst nodal deviation %.2f %%, %ld steps\n", mean,
              sigma, 100 * worst, s.steps());
}
