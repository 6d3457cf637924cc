// Band on a cylinder: a membrane strap of width w wrapped half-way around a rigid cylinder of
// radius R and pulled with tension T at both ends presses on it with p = T/(R·w) (the capstan
// equation without friction: the tension is constant along the wrap, each length ds carries
// T·ds/R of normal force).
//
// R = 20 mm, w = 10 mm, T = 1 N: p = 5 kPa. Strap: quad membranes, E = 10.2 MPa, 1 mm thick
// (the strap material of DESIGN.md), its wrap nodes on the cylinder's vertex angles (each strap
// facet lies on a cylinder facet), its straight legs hanging 10 mm down from θ = 0 and θ = π
// (both vertex angles); the end nodes are held in
// x and z and loaded with −T along y. The rigid cylinder (facets every 5°, from −30° to 210°) is
// the master; the strap (its facets: segment-to-surface) is the slave. Both are make_plate grids
// bent into shape. Why the strap nodes sit on the vertex angles: half-way between them, the strap
// chords would cut through the cylinder's vertices by R(1 − cos 2.5°) = 0.019 mm, comparable with
// the penalty gap, and the facet integration sees that faceting (5.9 % at 60°/120°, measured).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "solve/make_block.h"
#include "solve/solver.h"

TEST(contact_band, strap_pressure_on_a_cylinder_is_tension_over_radius_width) {
  const double R = 20, w = 10, T = 1, leg = 10, dth = 5 * M_PI / 180;
  const int nz = 4, n_leg = 6;
  const solve::Material strap{"strap", 1.1e-3, 10.2, 0.3, false};
  const solve::Material rigid{"cylinder", 1e-2, 1000, 0.3, true};
  // A plate from make_plate (node (i, j) at x = i, y = j) bent onto a polyline: plate column i
  // goes to point i of the polyline in the xy plane, plate row j to z = w·j/nz.
  auto bent_plate = [&](solve::ElementType type, const std::vector<std::array<double, 2>>& line,
                        const solve::Material& mat, const std::string& part) {
    solve::PlateSpec ps;
    ps.type = type;
    ps.nx = int(line.size()) - 1;
    ps.ny = nz;
    ps.size = {double(ps.nx), double(nz)};
    ps.part = part;
    solve::Model plate = solve::make_plate(ps, mat);
    for (std::size_t n = 0; n < plate.n_nodes(); ++n) {
      const std::size_t i = std::size_t(std::lround(plate.X[3 * n]));
      const long j = std::lround(plate.X[3 * n + 1]);
      plate.X[3 * n] = line[i][0];
      plate.X[3 * n + 1] = line[i][1];
      plate.X[3 * n + 2] = w * double(j) / nz;
    }
    return plate;
  };
  // 1. Strap: polyline right leg (bottom → top) → wrap → left leg (top → bottom).
  std::vector<std::array<double, 2>> line;
  for (int i = 0; i <= n_leg; ++i) line.push_back({R, -leg + leg * i / n_leg});
  const int n_wrap = int(std::lround(M_PI / dth));
  for (int j = 1; j < n_wrap; ++j) line.push_back({R * std::cos(j * dth), R * std::sin(j * dth)});
  for (int i = 0; i <= n_leg; ++i) line.push_back({-R, -leg * i / n_leg});
  solve::Model m = bent_plate(solve::ElementType::quad4, line, strap, "strap");
  m.name = "band";
  m.node_groups["end_right"] = m.group("xmin");
  m.node_groups["end_left"] = m.group("xmax");
  // 2. Cylinder: vertices every 5° from −30° to 210°, rows as the strap's. make_plate's facets
  // have (b − a) along +θ and (d − a) along +z, so their normals (b − a) × (c − a) point outward.
  std::vector<std::array<double, 2>> arc;
  const int n_arc = int(std::lround(240 * M_PI / 180 / dth));
  for (int j = 0; j <= n_arc; ++j) {
    const double th = -30 * M_PI / 180 + j * dth;
    arc.push_back({R * std::cos(th), R * std::sin(th)});
  }
  const int c0 = int(m.n_nodes());  // cylinder node (j, k) is c0 + j + (n_arc + 1)·k
  solve::append_model(m, bent_plate(solve::ElementType::tri3, arc, rigid, "cylinder"), "cyl_");
  // 3. Supports, loads, contact, control.
  using solve::BcKind;
  for (int d = 0; d < 3; ++d) m.bcs.push_back({"cyl_cylinder", d, BcKind::fixed, {}});
  for (const char* end : {"end_right", "end_left"}) {
    m.bcs.push_back({end, 0, BcKind::fixed, {}});
    m.bcs.push_back({end, 2, BcKind::fixed, {}});
    m.loads.push_back({end, 1, solve::Curve{{0, 4, 10}, {0, -T, -T}}});
  }
  solve::ContactDef c;
  c.name = "band_on_cylinder";
  c.slave = "strap";
  c.master = "cyl_cylinder";
  c.damping_ratio = 0.2;
  m.contacts.push_back(c);
  m.control.end_time = 10;
  m.control.damping_alpha = 1.0;
  solve::Solver s(m);
  s.run_until(10);
  ASSERT_EQ(s.health(), "");
  // 4. Pressure on the cylinder's mid-width vertex line over the middle 60° of the wrap, within 5 %
  // (the tolerance; statics makes it exact up to the facet chord/arc ratio 1 − 1e-4 and
  // the residual dynamics after 6 ms of damped hold).
  const double expected = T / (R * w);
  const auto p = s.contact_pressure();
  int checked = 0;
  double worst = 0;
  for (int j = 0; j <= n_arc; ++j) {
    const double th_deg = -30 + j * 5.0;
    if (th_deg < 60 || th_deg > 120) continue;
    const double pj = p[std::size_t(c0 + j + (n_arc + 1) * (nz / 2))];
    worst = std::max(worst, std::fabs(pj / expected - 1));
    EXPECT_NEAR(pj, expected, 0.05 * expected) << "at " << th_deg << "°";
    ++checked;
  }
  std::printf("band: p = T/(R·w) = %.5f MPa, worst error over 60–120° %.2f %%, %ld steps of %.2e ms\n", expected,
              100 * worst, s.steps(), s.dt());
  EXPECT_EQ(checked, 13);
}
