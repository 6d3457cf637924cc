// Hertz contact: a rigid sphere R = 10 mm pressed into a soft block (E = 0.6 MPa, ν = 0.45) with
// 1 N. Hertz: a = (3FR/4E*)^(1/3) ≈ 2.15 mm, p0 = 3F/(2πa²) ≈ 0.103 MPa, d = a²/R ≈ 0.46 mm.
//
// Quarter model (symmetry planes x = 0 and z = 0), block 16 × 16 × 16 mm (≈ 7a: the fixed base and
// the sides stiffen the half-space by a few %), hex mesh graded from h0 at the contact (uniform
// over 3 mm ≈ 1.4a) to ~3 mm at the far faces. The sphere is the rigid MASTER, triangulated on the block's own
// plan grid (its vertices above the block's top nodes). The block's top face is the slave
// surface, integrated over its facets (segment-to-surface), and the pressure, output on the
// master, is the gathered force over the gathered area; the facet chord error h0²/8R ≤ 1 µm is
// far below the penalty gap (~0.05 mm), so no "bed of nails". The sphere is pushed down by the
// Hertz indentation for 1 N (displacement control: no rigid-body oscillation), then held; the
// contact force F is measured and a, p0 are compared with Hertz at that F.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "contact_models.h"
#include "solve/solver.h"

namespace {

struct HertzResult {
  double force = 0, a = 0, p0 = 0;
};

constexpr double kR = 10, kE = 0.6, kNu = 0.45;
const double kEstar = kE / (1 - kNu * kNu);
double hertz_a(double F) { return std::cbrt(3 * F * kR / (4 * kEstar)); }
double hertz_p0(double F) { return 3 * F / (2 * M_PI * hertz_a(F) * hertz_a(F)); }

HertzResult run_hertz(double h0, double penalty_scale) {
  const double L = 16, fine = 3;
  const auto plan = contact_test::graded(h0, fine, L, 1.3);
  std::vector<double> ys = contact_test::graded(h0, fine, L, 1.3);  // depth from the top
  for (double& y : ys) y = -y;
  std::reverse(ys.begin(), ys.end());
  solve::Material tissue;
  tissue.name = "block";
  tissue.density = 1e-3;
  tissue.E = kE;
  tissue.nu = kNu;
  solve::Model m = contact_test::graded_block(plan, ys, plan, tissue);
  const double cap = 4.2;  // master radius in plan view [mm] (contact radius ≈ 2.2)
  const solve::Model sphere = contact_test::rigid_surface(
      plan, plan, [](double x, double z) { return kR - std::sqrt(kR * kR - x * x - z * z); },
      [&](double x, double z) { return x * x + z * z <= cap * cap; }, "sphere");
  solve::append_model(m, sphere, "");
  const double d = hertz_a(1.0) * hertz_a(1.0) / kR, t_load = 6, t_end = 10;
  using solve::BcKind;
  m.bcs.push_back({"ymin", 0, BcKind::fixed, {}});
  m.bcs.push_back({"ymin", 1, BcKind::fixed, {}});
  m.bcs.push_back({"ymin", 2, BcKind::fixed, {}});
  m.bcs.push_back({"xmin", 0, BcKind::fixed, {}});  // symmetry planes
  m.bcs.push_back({"zmin", 2, BcKind::fixed, {}});
  m.bcs.push_back({"sphere", 0, BcKind::fixed, {}});
  m.bcs.push_back({"sphere", 2, BcKind::fixed, {}});
  m.bcs.push_back({"sphere", 1, BcKind::displacement, solve::Curve{{0, t_load, t_end}, {0, -d, -d}}});
  solve::ContactDef c;
  c.name = "sphere_on_block";
  c.slave = "ymax";
  c.master = "sphere";
  c.damping_ratio = 0.2;
  // Penalty scale: the penalty springs act as a soft layer in series with the block, of stiffness
  // per area ~ s·ρ·h/Δt² ~ s·E/h against the half-space's ~E*/a, so their share of the
  // approach falls as h0/a. With the paper's s = 0.1 and segment-to-surface contact, p0 is
  // −12.7 % (h0 = 0.3), −8.6 % (h0 = 0.2), −6.5 % (h0 = 0.15) off Hertz (measured): the default
  // needs h0 ≤ 0.2 mm (a/h0 ≥ 11) here.
  c.penalty_scale = penalty_scale;
  m.contacts.push_back(c);
  m.control.end_time = t_end;
  m.control.damping_alpha = 1.5;  // ≈ critical for the block's first modes (periods ~4 ms)
  // Mass scaling of the small cells near the contact (the far cells are 10× larger): halves the
  // steps. It adds 1.0 g to the block's 4.1 g (measured); the answer is static, and in the
  // scaled cells the penalty k = s·m/Δt² is unchanged (m grows as Δt²).
  m.control.dt_target = 0.02 * h0;  // about twice the stable step of the h0 cells
  solve::Solver s(m);
  s.run_until(t_end);
  EXPECT_EQ(s.health(), "");
  // Measurements on the master (sphere) nodes.
  HertzResult r;
  r.force = -4 * s.contacts()[0].resultant_force()[1];  // quarter model, force on the block is −y
  const auto p = s.contact_pressure();
  const auto& x = s.x();
  std::vector<std::pair<double, double>> rp;  // (r², p)
  double p_pole = 0;
  for (int id : s.model().group("sphere")) {
    const double px = x[3 * std::size_t(id)], pz = x[3 * std::size_t(id) + 2], r2 = px * px + pz * pz;
    if (r2 < 1e-12) p_pole = p[std::size_t(id)];
    // The pole is the quarter model's corner: its lumped area (1/3 of its two facets, h0²/3) is
    // not the quarter cell h0²/4 the slave's force stands for, so its value reads 25 % low — an
    // artefact of cutting the model, not of contact; it is left out of the fit.
    else rp.push_back({r2, p[std::size_t(id)]});
  }
  // a and p0: least-squares fit of the Hertz shape p² = p0² (1 − r²/a²) over the nodes above
  // 30 % of the peak (the penalty rounds off the last ~h0 at the edge).
  double p_max = 0;
  for (auto [r2, pi] : rp) p_max = std::max(p_max, pi);
  double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (auto [r2, pi] : rp)
    if (pi > 0.3 * p_max) {
      sw += 1, sx += r2, sy += pi * pi, sxx += r2 * r2, sxy += r2 * pi * pi;
    }
  const double slope = (sw * sxy - sx * sy) / (sw * sxx - sx * sx), icept = (sy - slope * sx) / sw;
  r.a = std::sqrt(-icept / slope);
  r.p0 = std::sqrt(icept);
  std::printf("hertz h0 = %.2f mm, s = %.1f: F = %.4f N, a = %.3f mm (Hertz %.3f), p0 = %.4f MPa (Hertz %.4f; "
              "largest nodal %.4f, pole %.4f), dt = %.2e ms (stable %.2e, added mass %.2e g), %ld steps\n",
              h0, penalty_scale, r.force, r.a, hertz_a(r.force), r.p0, hertz_p0(r.force), p_max, p_pole, s.dt(),
              s.stable_dt(), s.added_mass(), s.steps());
  return r;
}

}  // namespace

TEST(contact_hertz, sphere_on_soft_block_matches_hertz_on_two_meshes) {
  // 10 % (the tolerance) on a and p0, against Hertz at the measured force (the pressure
  // distribution depends on F only), with the paper's default penalty scale s = 0.1. The force at
  // the Hertz indentation for 1 N comes out +4 to +6 % (measured): the 7a block with a held base
  // is stiffer than a half-space in the far field, which shifts the approach d but not a(F),
  // p0(F); checked within 15 %. Mesh convergence: the two meshes (h0 = 0.2 and 0.15 mm, a/h0 ≈ 11
  // and 15) agree within 5 % on a and p0 (measured 0.1 % and 3.0 %).
  const double s = solve::ContactDef{}.penalty_scale;  // the default (0.1)
  const HertzResult coarse = run_hertz(0.2, s), fine = run_hertz(0.15, s);
  for (const HertzResult& r : {coarse, fine}) {
    EXPECT_NEAR(r.force, 1.0, 0.15);
    EXPECT_NEAR(r.a / hertz_a(r.force), 1.0, 0.10);
    EXPECT_NEAR(r.p0 / hertz_p0(r.force), 1.0, 0.10);
  }
  EXPECT_NEAR(fine.a / coarse.a, 1.0, 0.05);
  EXPECT_NEAR(fine.p0 / coarse.p0, 1.0, 0.05);
}
