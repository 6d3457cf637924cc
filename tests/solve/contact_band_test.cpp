// Band on a cylinder: a membrane strap of width w wrapped half-way around a rigid cylinder of
// radius R and pulled with tension T at both ends presses on it with p = T/(R·w) (the capstan
// equation without friction: the tension is constant along the wrap, each length ds carries
// T·ds/R of normal force).
//
// R = 20 mm, w = 10 mm, T = 1 N: p = 5 kPa. Strap: quad membranes, E = 10.2 MPa, 1 mm thick
// (the strap material of DESIGN.md), its wrap nodes half-way between the cylinder's vertex
// angles (so each strap node sits over the middle of a facet and the faceted cylinder pushes it
// radially), its straight legs hanging 10 mm down from θ = 0 and θ = π; the end nodes are held in
// x and z and loaded with −T along y. The rigid cylinder (facets every 5°, from −30° to 210°) is
// the master; the strap nodes are the slaves.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "solve/make_block.h"
#include "solve/solver.h"

TEST(contact_band, strap_pressure_on_a_cylinder_is_tension_over_radius_width) {
  const double R = 20, w = 10, T = 1, leg = 10, dth = 5 * M_PI / 180;
  const int nz = 4, n_leg = 6;
  solve::Model m;
  m.name = "band";
  solve::Material strap{"strap", 1.1e-3, 10.2, 0.3, false};
  solve::Material rigid{"cylinder", 1e-2, 1000, 0.3, true};
  m.materials = {strap, rigid};
  auto add_node = [&](double x, double y, double z) {
    m.X.insert(m.X.end(), {x, y, z});
    m.node_tags.push_back(long(m.n_nodes()));
    return int(m.n_nodes()) - 1;
  };
  // 1. Strap: polyline right leg (bottom → top) → wrap → left leg (top → bottom), × nz+1 lines.
  std::vector<std::array<double, 2>> line;
  for (int i = 0; i <= n_leg; ++i) line.push_back({R, -leg + leg * i / n_leg});
  const int n_wrap = int(std::lround(M_PI / dth));
  for (int j = 0; j < n_wrap; ++j) line.push_back({R * std::cos((j + 0.5) * dth), R * std::sin((j + 0.5) * dth)});
  for (int i = 0; i <= n_leg; ++i) line.push_back({-R, -leg * i / n_leg});
  std::vector<std::vector<int>> id(line.size());
  for (std::size_t i = 0; i < line.size(); ++i)
    for (int k = 0; k <= nz; ++k) {
      id[i].push_back(add_node(line[i][0], line[i][1], w * k / nz));
      m.node_groups["strap"].push_back(id[i].back());
    }
  solve::Part sp{"strap", solve::ElementType::quad4, 0, 1.0, {}};
  for (std::size_t i = 0; i + 1 < line.size(); ++i)
    for (int k = 0; k < nz; ++k)
      sp.conn.insert(sp.conn.end(), {id[i][std::size_t(k)], id[i + 1][std::size_t(k)],
                                     id[i + 1][std::size_t(k) + 1], id[i][std::size_t(k) + 1]});
  m.parts.push_back(sp);
  m.node_groups["end_right"] = id.front();
  m.node_groups["end_left"] = id.back();
  // 2. Cylinder: vertices every 5° from −30° to 210°, z lines as the strap's; outward normals.
  const int c0 = int(m.n_nodes()), n_arc = int(std::lround(240 * M_PI / 180 / dth));
  for (int j = 0; j <= n_arc; ++j)
    for (int k = 0; k <= nz; ++k) {
      const double th = -30 * M_PI / 180 + j * dth;
      m.node_groups["cylinder"].push_back(add_node(R * std::cos(th), R * std::sin(th), w * k / nz));
    }
  solve::Part cp{"cylinder", solve::ElementType::tri3, 1, 1.0, {}};
  auto& tris = m.surfaces["cylinder"];
  for (int j = 0; j < n_arc; ++j)
    for (int k = 0; k < nz; ++k) {
      const int a = c0 + j * (nz + 1) + k, b = a + nz + 1, c = b + 1, d = a + 1;
      // (b − a) is along +θ, (d − a) along +z: (b − a) × (d − a) points outward.
      tris.push_back({a, b, c});
      tris.push_back({a, c, d});
      cp.conn.insert(cp.conn.end(), {a, b, c, a, c, d});
    }
  m.parts.push_back(cp);
  // 3. Supports, loads, contact, control.
  using solve::BcKind;
  for (int d = 0; d < 3; ++d) m.bcs.push_back({"cylinder", d, BcKind::fixed, {}});
  for (const char* end : {"end_right", "end_left"}) {
    m.bcs.push_back({end, 0, BcKind::fixed, {}});
    m.bcs.push_back({end, 2, BcKind::fixed, {}});
    m.loads.push_back({end, 1, solve::Curve{{0, 4, 10}, {0, -T, -T}}});
  }
  solve::ContactDef c;
  c.name = "band_on_cylinder";
  c.slave = "strap";
  c.master = "cylinder";
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
    const double pj = p[std::size_t(c0 + j * (nz + 1) + nz / 2)];
    worst = std::max(worst, std::fabs(pj / expected - 1));
    EXPECT_NEAR(pj, expected, 0.05 * expected) << "at " << th_deg << "°";
    ++checked;
  }
  std::printf("band: p = T/(R·w) = %.5f MPa, worst error over 60–120° %.2f %%, %ld steps of %.2e ms\n", expected,
              100 * worst, s.steps(), s.dt());
  EXPECT_EQ(checked, 13);
}
