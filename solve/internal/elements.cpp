#include "solve/internal/elements.h"

#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Dense>

#include "pipeline/error.h"

namespace solve::internal {
namespace {

// ---------- hot kernels ----------
// Stiffness hourglass control of one element, shared by solids and membranes: for each γ-vector
// g_h (orthogonal to the affine fields) the mode amplitude q_h = Σ_a g_ha x_a, force
// f_a −= k g_ha q_h. g: NH×NN γ-vectors of the element, k its hourglass stiffness.
template <int NN, int NH>
inline void add_hourglass_forces(const double* g, double k, const double (&xe)[NN][3], double* f) {
  for (int h = 0; h < NH; ++h) {
    double q[3] = {0, 0, 0};
    for (int a = 0; a < NN; ++a)
      for (int i = 0; i < 3; ++i) q[i] += g[h * NN + a] * xe[a][i];
    for (int a = 0; a < NN; ++a)
      for (int i = 0; i < 3; ++i) f[3 * a + i] -= k * g[h * NN + a] * q[i];
  }
}

template <int NN, int NH>
int solid_forces(const ElementBlock& blk, const double* x, double* fe) {
  const long ne = long(blk.size());
  const double mu = blk.mu, lam = blk.lambda;
  const int* conn = blk.conn.data();
  const double* B = blk.b.data();
  const double* G = blk.gamma.data();
  int inverted = 0;
#pragma omp parallel for schedule(static) if (ne > kMinParallel) reduction(+ : inverted)
  for (long e = 0; e < ne; ++e) {
    double xe[NN][3];
    for (int a = 0; a < NN; ++a) {
      const double* p = x + 3 * std::size_t(conn[e * NN + a]);
      xe[a][0] = p[0]; xe[a][1] = p[1]; xe[a][2] = p[2];
    }
    const double* b = B + std::size_t(e) * NN * 3;
    double F[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (int a = 0; a < NN; ++a)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) F[i][j] += xe[a][i] * b[3 * a + j];
    // cofactor matrix = J F⁻ᵀ
    double c[3][3];
    c[0][0] = F[1][1] * F[2][2] - F[1][2] * F[2][1];
    c[0][1] = F[1][2] * F[2][0] - F[1][0] * F[2][2];
    c[0][2] = F[1][0] * F[2][1] - F[1][1] * F[2][0];
    c[1][0] = F[0][2] * F[2][1] - F[0][1] * F[2][2];
    c[1][1] = F[0][0] * F[2][2] - F[0][2] * F[2][0];
    c[1][2] = F[0][1] * F[2][0] - F[0][0] * F[2][1];
    c[2][0] = F[0][1] * F[1][2] - F[0][2] * F[1][1];
    c[2][1] = F[0][2] * F[1][0] - F[0][0] * F[1][2];
    c[2][2] = F[0][0] * F[1][1] - F[0][1] * F[1][0];
    const double J = F[0][0] * c[0][0] + F[0][1] * c[0][1] + F[0][2] * c[0][2];
    double P[3][3];
    if (J > 0) {
      const double s = (lam * std::log(J) - mu) / J;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) P[i][j] = mu * F[i][j] + s * c[i][j];
    } else {
      ++inverted;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) P[i][j] = 0;
    }
    const double V = blk.vol[e];
    double* f = fe + blk.force_offset + std::size_t(e) * NN * 3;
    for (int a = 0; a < NN; ++a)
      for (int i = 0; i < 3; ++i)
        f[3 * a + i] = -V * (P[i][0] * b[3 * a] + P[i][1] * b[3 * a + 1] + P[i][2] * b[3 * a + 2]);
    add_hourglass_forces<NN, NH>(G + std::size_t(e) * NH * NN, blk.khg[e], xe, f);
  }
  return inverted;
}

// Membrane: g_α = Σ x_a β_aα (current images of the reference in-plane unit vectors).
template <int NN, int NH>
int membrane_forces(const ElementBlock& blk, const double* x, double* fe) {
  const long ne = long(blk.size());
  const double D = blk.E / (1 - blk.nu * blk.nu), G2 = blk.E / (1 + blk.nu), nu = blk.nu;
  int inverted = 0;
#pragma omp parallel for schedule(static) if (ne > kMinParallel) reduction(+ : inverted)
  for (long e = 0; e < ne; ++e) {
    double xe[NN][3];
    for (int a = 0; a < NN; ++a) {
      const double* p = x + 3 * std::size_t(blk.conn[e * NN + a]);
      xe[a][0] = p[0]; xe[a][1] = p[1]; xe[a][2] = p[2];
    }
    const double* b = blk.b.data() + std::size_t(e) * NN * 2;
    double g1[3] = {0, 0, 0}, g2[3] = {0, 0, 0};
    for (int a = 0; a < NN; ++a)
      for (int i = 0; i < 3; ++i) { g1[i] += xe[a][i] * b[2 * a]; g2[i] += xe[a][i] * b[2 * a + 1]; }
    const double E11 = 0.5 * (g1[0] * g1[0] + g1[1] * g1[1] + g1[2] * g1[2] - 1);
    const double E22 = 0.5 * (g2[0] * g2[0] + g2[1] * g2[1] + g2[2] * g2[2] - 1);
    const double E12 = 0.5 * (g1[0] * g2[0] + g1[1] * g2[1] + g1[2] * g2[2]);
    const double S11 = D * (E11 + nu * E22), S22 = D * (E22 + nu * E11), S12 = G2 * E12;
    const double V = blk.vol[e];
    double* f = fe + blk.force_offset + std::size_t(e) * NN * 3;
    for (int a = 0; a < NN; ++a) {
      const double c1 = S11 * b[2 * a] + S12 * b[2 * a + 1], c2 = S12 * b[2 * a] + S22 * b[2 * a + 1];
      for (int i = 0; i < 3; ++i) f[3 * a + i] = -V * (g1[i] * c1 + g2[i] * c2);
    }
    add_hourglass_forces<NN, NH>(blk.gamma.data() + std::size_t(e) * NH * NN, blk.khg[e], xe, f);
  }
  return inverted;
}

// Mean deformation gradient of element e (solids: 3×3; membranes: columns g1, g2, and 0).
void mean_F(const ElementBlock& blk, std::size_t e, const double* x, double F[3][3]) {
  for (int i = 0; i < 3; ++i) for (int j = 0; j < 3; ++j) F[i][j] = 0;
  const int nn = blk.nn, d = blk.dim;
  for (int a = 0; a < nn; ++a) {
    const double* p = x + 3 * std::size_t(blk.conn[e * nn + a]);
    const double* b = blk.b.data() + (e * nn + a) * d;
    for (int i = 0; i < 3; ++i) for (int j = 0; j < d; ++j) F[i][j] += p[i] * b[j];
  }
}

double hourglass_energy(const ElementBlock& blk, std::size_t e, const double* x) {
  double w = 0;
  const int nn = blk.nn;
  for (int h = 0; h < blk.nh; ++h) {
    double q[3] = {0, 0, 0};
    for (int a = 0; a < nn; ++a) {
      const double* p = x + 3 * std::size_t(blk.conn[e * nn + a]);
      const double g = blk.gamma[(e * blk.nh + h) * nn + a];
      for (int i = 0; i < 3; ++i) q[i] += g * p[i];
    }
    w += 0.5 * blk.khg[e] * (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  }
  return w;
}

}  // namespace

int forces_for_elems(const ElementBlock& blk, const double* x, double* fe) {
  switch (blk.type) {
    case ElementType::wedge6: return solid_forces<6, 2>(blk, x, fe);
    case ElementType::hex8: return solid_forces<8, 4>(blk, x, fe);
    case ElementType::tet4: return solid_forces<4, 0>(blk, x, fe);
    case ElementType::quad4: return membrane_forces<4, 1>(blk, x, fe);
    case ElementType::tri3: return membrane_forces<3, 0>(blk, x, fe);
  }
  return 0;
}

double energy_for_elems(const ElementBlock& blk, const double* x) {
  const long ne = long(blk.size());
  double w = 0;
#pragma omp parallel for schedule(static) if (ne > kMinParallel) reduction(+ : w)
  for (long e = 0; e < ne; ++e) {
    double F[3][3];
    mean_F(blk, e, x, F);
    double we;
    if (blk.dim == 3) {
      const double J = F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) -
                       F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
                       F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]);
      double I1 = 0;
      for (int i = 0; i < 3; ++i) for (int j = 0; j < 3; ++j) I1 += F[i][j] * F[i][j];
      const double lj = J > 0 ? std::log(J) : 0.0;
      we = 0.5 * blk.mu * (I1 - 3) - blk.mu * lj + 0.5 * blk.lambda * lj * lj;
    } else {
      double C[2][2];
      for (int a = 0; a < 2; ++a) for (int c = 0; c < 2; ++c) C[a][c] = F[0][a] * F[0][c] + F[1][a] * F[1][c] + F[2][a] * F[2][c];
      const double E11 = 0.5 * (C[0][0] - 1), E22 = 0.5 * (C[1][1] - 1), E12 = 0.5 * C[0][1];
      const double D = blk.E / (1 - blk.nu * blk.nu);
      we = 0.5 * D * (E11 * E11 + E22 * E22 + 2 * blk.nu * E11 * E22) + blk.E / (1 + blk.nu) * E12 * E12;
    }
    w += blk.vol[e] * we + hourglass_energy(blk, e, x);
  }
  return w;
}

void von_mises_for_elems(const ElementBlock& blk, const double* x, double* vm) {
  const long ne = long(blk.size());
#pragma omp parallel for schedule(static) if (ne > kMinParallel)
  for (long e = 0; e < ne; ++e) {
    double F[3][3];
    mean_F(blk, e, x, F);
    Eigen::Matrix3d s;
    if (blk.dim == 3) {
      Eigen::Matrix3d Fm;
      for (int i = 0; i < 3; ++i) for (int j = 0; j < 3; ++j) Fm(i, j) = F[i][j];
      const double J = Fm.determinant();
      if (!(J > 0)) { vm[e] = 0; continue; }
      // Cauchy: σ = (μ (b − I) + λ ln J I) / J
      s = (blk.mu * (Fm * Fm.transpose() - Eigen::Matrix3d::Identity()) +
           blk.lambda * std::log(J) * Eigen::Matrix3d::Identity()) / J;
    } else {
      Eigen::Matrix<double, 3, 2> g;
      for (int i = 0; i < 3; ++i) { g(i, 0) = F[i][0]; g(i, 1) = F[i][1]; }
      Eigen::Matrix2d C = g.transpose() * g, E = 0.5 * (C - Eigen::Matrix2d::Identity()), S;
      const double D = blk.E / (1 - blk.nu * blk.nu);
      S(0, 0) = D * (E(0, 0) + blk.nu * E(1, 1));
      S(1, 1) = D * (E(1, 1) + blk.nu * E(0, 0));
      S(0, 1) = S(1, 0) = blk.E / (1 + blk.nu) * E(0, 1);
      const double j = std::sqrt(std::max(C.determinant(), 1e-300));  // area ratio
      s = g * S * g.transpose() / j;
    }
    const double p = s.trace() / 3;
    const Eigen::Matrix3d dev = s - p * Eigen::Matrix3d::Identity();
    vm[e] = std::sqrt(1.5 * dev.cwiseProduct(dev).sum());
  }
}

namespace {
// Upper bound of ω² of one element: lumped mass ρV/nn per node and K = V BᵀDB + hourglass.
// Solids: εᵀDε = λ(tr ε)² + 2μ ε:ε ≤ (λ+2μ) Σ|u_a|² Σ|b_a|² (Cauchy–Schwarz on tr ε and on
// |Σ u_a⊗b_a|), with the current tangent λ+2μ+2λ|ln J| of the neo-Hookean law. Membranes: the
// largest eigenvalue of plane-stress D is E/(1−ν). Hourglass: λmax(kΣγγᵀ) ≤ k Σ|γ|² = κμVΣ|b|²·nh.
double omega2_bound(const ElementBlock& blk, double bb, double J) {
  const double nnr = blk.nn / blk.rho;
  double modulus;
  if (blk.dim == 2) {
    modulus = blk.E / (1 - blk.nu);
  } else {
    const double lj = J > 0 ? std::fabs(std::log(J)) : 0.0;
    modulus = blk.lambda + 2 * blk.mu + 2 * blk.lambda * lj;
  }
  return nnr * bb * (modulus + blk.kappa * blk.mu * blk.nh);
}
}  // namespace

std::vector<double> element_dt(const ElementBlock& blk, const double* X) {
  std::vector<double> dt(blk.size(), std::numeric_limits<double>::infinity());
  if (blk.rigid) return dt;
  const int nn = blk.nn, d = blk.dim;
  for (std::size_t e = 0; e < blk.size(); ++e) {
    double bb = 0;
    for (int k = 0; k < nn * d; ++k) bb += blk.b[e * nn * d + k] * blk.b[e * nn * d + k];
    dt[e] = 2.0 / std::sqrt(omega2_bound(blk, bb, 1.0));
  }
  return dt;
}

double stable_dt_for_elems(const ElementBlock& blk, const double* x, const std::vector<double>& mass_factor,
                           const std::vector<char>* skip) {
  double dtmin = std::numeric_limits<double>::infinity();
  if (blk.rigid) return dtmin;
  const long ne = long(blk.size());
  const int nn = blk.nn, d = blk.dim;
#pragma omp parallel for schedule(static) if (ne > kMinParallel) reduction(min : dtmin)
  for (long e = 0; e < ne; ++e) {
    if (skip && (*skip)[std::size_t(e)]) continue;
    double F[3][3];
    mean_F(blk, e, x, F);
    double bb = 0, J = 1;
    if (d == 3) {
      Eigen::Matrix3d Fm;
      for (int i = 0; i < 3; ++i) for (int j = 0; j < 3; ++j) Fm(i, j) = F[i][j];
      J = Fm.determinant();
      if (!(J > 0)) continue;  // inverted elements are caught by the force kernel
      const Eigen::Matrix3d Fit = Fm.inverse().transpose();
      for (int a = 0; a < nn; ++a) {
        Eigen::Vector3d ba(&blk.b[(e * nn + a) * 3]);
        bb += (Fit * ba).squaredNorm();
      }
    } else {
      // membranes: stiffness grows with stretch²; bound it with the largest current stretch.
      double s2 = 1;
      for (int j = 0; j < 2; ++j) s2 = std::max(s2, F[0][j] * F[0][j] + F[1][j] * F[1][j] + F[2][j] * F[2][j]);
      for (int k = 0; k < nn * 2; ++k) bb += blk.b[e * nn * 2 + k] * blk.b[e * nn * 2 + k];
      bb *= s2;
    }
    double w2 = omega2_bound(blk, bb, J);
    if (!mass_factor.empty()) w2 /= mass_factor[e];
    dtmin = std::min(dtmin, 2.0 / std::sqrt(w2));
  }
  return dtmin;
}

}  // namespace solve::internal
