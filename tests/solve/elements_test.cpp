// Element verification: patch tests (uniform strain reproduced exactly on irregular meshes of
// every element type) and objectivity (rigid rotation leaves stress invariant).
#include <gtest/gtest.h>

#include <cmath>

#include "solve/make_block.h"
#include "solve/solver.h"

namespace {

using solve::ElementType;

solve::Material rubber() { return {"rubber", 1e-3, 1.0, 0.3, false}; }

// A general (non-symmetric) deformation gradient: 5 % to 15 % strains with shear.
const double A[3][3] = {{1.10, 0.05, -0.03}, {0.02, 0.93, 0.04}, {-0.01, 0.06, 1.15}};

// Maps every node through x = M·X and takes one step, whose internal_force() is evaluated on
// that configuration. Returns the nodal von Mises stress of the mapped configuration.
std::vector<double> set_positions(solve::Solver& s, const double M[3][3]) {
  solve::SolverState st = s.state();
  for (std::size_t i = 0; i < st.X.size() / 3; ++i)
    for (int r = 0; r < 3; ++r) {
      st.x[3 * i + r] = 0;
      for (int c = 0; c < 3; ++c) st.x[3 * i + r] += M[r][c] * st.X[3 * i + c];
    }
  std::fill(st.v.begin(), st.v.end(), 0.0);
  s.set_state(st);
  auto vm = s.von_mises();
  s.step();
  return vm;
}

bool on_boundary(const solve::Model& m, int id) {
  for (const char* g : {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"}) {
    auto it = m.node_groups.find(g);
    if (it != m.node_groups.end() && std::binary_search(it->second.begin(), it->second.end(), id)) return true;
  }
  return false;
}

// Patch test: in a uniform strain field the interior nodes are in equilibrium and the stress is
// the same in every element. Tolerance 1e-10 relative to the largest nodal force: the forces are
// sums of O(10) terms of that size in double precision (round-off ~1e-15 each), so anything above
// 1e-10 is a formulation error, not round-off.
void patch_test(const solve::Model& m) {
  solve::Solver s(m);
  const auto vm = set_positions(s, A);
  const auto& f = s.internal_force();
  double fmax = 0, finner = 0;
  int inner = 0;
  for (std::size_t i = 0; i < m.n_nodes(); ++i) {
    const double fn = std::sqrt(f[3 * i] * f[3 * i] + f[3 * i + 1] * f[3 * i + 1] + f[3 * i + 2] * f[3 * i + 2]);
    fmax = std::max(fmax, fn);
    if (!on_boundary(m, int(i))) { finner = std::max(finner, fn); ++inner; }
  }
  ASSERT_GT(inner, 0);
  ASSERT_GT(fmax, 0);
  EXPECT_LT(finner, 1e-10 * fmax);
  double lo = 1e300, hi = 0;
  for (double x : vm) { lo = std::min(lo, x); hi = std::max(hi, x); }
  EXPECT_GT(lo, 0);
  EXPECT_LT(hi - lo, 1e-10 * hi);
}

solve::Model irregular_block(ElementType t) {
  solve::BlockSpec b;
  b.type = t;
  b.nx = 4; b.ny = 3; b.nz = 3;
  b.size = {4, 3, 2.5};
  b.jitter = 0.25;
  return solve::make_block(b, rubber());
}

}  // namespace

TEST(patch_test, wedge_irregular_mesh_uniform_strain_exact) { patch_test(irregular_block(ElementType::wedge6)); }
TEST(patch_test, hex_irregular_mesh_uniform_strain_exact) { patch_test(irregular_block(ElementType::hex8)); }
TEST(patch_test, tet_irregular_mesh_uniform_strain_exact) { patch_test(irregular_block(ElementType::tet4)); }

class membrane_patch : public ::testing::TestWithParam<ElementType> {};
INSTANTIATE_TEST_SUITE_P(patch_test, membrane_patch, ::testing::Values(ElementType::quad4, ElementType::tri3));

TEST_P(membrane_patch, irregular_mesh_uniform_strain_exact) {
  solve::PlateSpec p;
  p.type = GetParam();
  p.nx = 5; p.ny = 4;
  p.size = {5, 4};
  p.jitter = 0.25;
  p.thickness = 0.5;
  // in-plane stretch and shear, then a tilt out of the plane: still a uniform membrane strain
  const double M[3][3] = {{1.08, 0.04, 0}, {0.03, 0.95, 0}, {0.0, 0.2, 0}};
  solve::Model m = solve::make_plate(p, rubber());
  solve::Solver s(m);
  set_positions(s, M);
  const auto& f = s.internal_force();
  double fmax = 0, finner = 0;
  for (std::size_t i = 0; i < m.n_nodes(); ++i) {
    const double fn = std::sqrt(f[3 * i] * f[3 * i] + f[3 * i + 1] * f[3 * i + 1] + f[3 * i + 2] * f[3 * i + 2]);
    fmax = std::max(fmax, fn);
    if (!on_boundary(m, int(i))) finner = std::max(finner, fn);
  }
  ASSERT_GT(fmax, 0);
  EXPECT_LT(finner, 1e-10 * fmax);
}

// A 90° rotation about z of a pre-stressed block: von Mises stress unchanged, nodal
// forces rotated with the body. Tolerance 1e-12 relative: the rotation matrix is exact (0, ±1),
// so only round-off of the stress evaluation remains.
TEST(objectivity, rotation_90deg_of_prestressed_block_keeps_stress) {
  for (ElementType t : {ElementType::wedge6, ElementType::hex8, ElementType::tet4}) {
    solve::Model m = irregular_block(t);
    solve::Solver a(m), b(m);
    const auto va = set_positions(a, A);
    const double R[3][3] = {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}};
    double RA[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        RA[i][j] = 0;
        for (int k = 0; k < 3; ++k) RA[i][j] += R[i][k] * A[k][j];
      }
    const auto vb = set_positions(b, RA);
    // energies of the stepped states differ; compare the mapped configurations' forces and stress

    ASSERT_GT(va[0], 0);
    for (std::size_t i = 0; i < va.size(); ++i) EXPECT_NEAR(vb[i], va[i], 1e-12 * va[i]);
    const auto& fa = a.internal_force();
    const auto& fb = b.internal_force();
    double fmax = 0, err = 0;
    for (std::size_t i = 0; i < m.n_nodes(); ++i)
      for (int r = 0; r < 3; ++r) {
        double rf = 0;
        for (int c = 0; c < 3; ++c) rf += R[r][c] * fa[3 * i + c];
        err = std::max(err, std::fabs(fb[3 * i + r] - rf));
        fmax = std::max(fmax, std::fabs(fa[3 * i + r]));
      }
    EXPECT_LT(err, 1e-12 * fmax) << solve::element_name(t);
  }
}

// A rigid rotation of the unstressed block (45° about an oblique axis) gives zero stress and zero
// forces: absolute 1e-12 MPa against stresses of order E·strain ~ 0.1 MPa in the tests above.
TEST(objectivity, rigid_rotation_gives_zero_stress) {
  const double c = std::cos(M_PI / 4), s = std::sin(M_PI / 4);
  // rotation about x then z
  const double R[3][3] = {{c, -s * c, s * s}, {s, c * c, -c * s}, {0, s, c}};
  for (ElementType t : {ElementType::wedge6, ElementType::hex8, ElementType::tet4}) {
    solve::Solver a(irregular_block(t));
    for (double v : set_positions(a, R)) EXPECT_LT(v, 1e-12);
    for (double f : a.internal_force()) EXPECT_LT(std::fabs(f), 1e-12);
  }
}

// The von Mises stress against its closed form (the tests above compare it only with itself): a
// uniaxial stretch F = diag(λ1, 1, 1) of the neo-Hookean solid gives Cauchy σ = (μ(b − I) + λ ln J I)/J
// with b = diag(λ1², 1, 1), J = λ1, so σ11 − σ22 = μ(λ1² − 1)/λ1, σ22 = σ33, and von Mises is
// |σ11 − σ22|. Rubber: μ = E/2(1+ν) = 1/2.6 MPa; λ1 = 1.1 gives 0.0734266 MPa. Every node of
// every element type, to 1e-9 relative (round-off, as in the patch tests). A √2 slip in the
// invariant (√(3 s:s) for √(1.5 s:s)) survived every test before this one (sweep L).
TEST(von_mises, uniaxial_stretch_matches_the_closed_form) {
  const double stretch = 1.1, mu = 1.0 / (2 * 1.3);
  const double expected = mu * (stretch * stretch - 1) / stretch;
  const double M[3][3] = {{stretch, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (ElementType t : {ElementType::wedge6, ElementType::hex8, ElementType::tet4}) {
    solve::Solver s(irregular_block(t));
    const auto vm = set_positions(s, M);
    ASSERT_FALSE(vm.empty());
    for (double v : vm) EXPECT_NEAR(v, expected, 1e-9 * expected) << int(t);
  }
}

// A membrane (the straps) stretched by λ along x and free across, in plane stress: with the
// St. Venant-Kirchhoff law S = D E, the lateral stretch λt that leaves S22 = 0 is
// sqrt(1 − ν(λ² − 1)), S11 = E·E11, and the Cauchy stress over the deformed area (ratio λ·λt) is
// σ11 = λ² S11 / (λ λt), its von Mises value. An area ratio taken as det C, (λ λt)², passed every
// test (sweep N).
TEST(von_mises, uniaxial_stretch_of_a_membrane_matches_the_closed_form) {
  const double E = 1.0, nu = 0.3, stretch = 1.2;
  const double e11 = 0.5 * (stretch * stretch - 1), across = std::sqrt(1 - nu * (stretch * stretch - 1));
  const double expected = stretch * stretch * E * e11 / (stretch * across);
  const double M[3][3] = {{stretch, 0, 0}, {0, across, 0}, {0, 0, 1}};
  for (ElementType t : {ElementType::quad4, ElementType::tri3}) {
    solve::PlateSpec ps;
    ps.type = t;
    ps.nx = 2;
    ps.ny = 3;
    ps.size = {2, 3};
    solve::Solver s(solve::make_plate(ps, {"m", 1e-3, E, nu, false}));
    const auto vm = set_positions(s, M);
    ASSERT_FALSE(vm.empty());
    for (double v : vm) EXPECT_NEAR(v, expected, 1e-9 * expected) << int(t);
  }
}
