#include "solve/internal/elements.h"

#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "pipeline/error.h"

// Set-up of the element blocks: reference shape functions, exact mean gradients b_a,
// hourglass vectors γ and stiffnesses (once per run; Eigen is fine here).
namespace solve::internal {
namespace {
// ---------- reference element data (setup only; Eigen is fine here) ----------
struct QuadPoint { double xi[3]; double w; };

// Natural coordinates of the nodes (gmsh orderings).
const double kHexNodes[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
const double kWedgeNodes[6][3] = {{0, 0, -1}, {1, 0, -1}, {0, 1, -1}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
const double kQuadNodes[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};

// dN/dξ (nn×d) at a natural point.
Eigen::MatrixXd shape_derivatives(ElementType t, const double* p) {
  const double xi = p[0], eta = p[1], ze = p[2];
  switch (t) {
    case ElementType::tet4: {
      Eigen::MatrixXd d(4, 3);
      d << -1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1;
      return d;
    }
    case ElementType::hex8: {
      Eigen::MatrixXd d(8, 3);
      for (int a = 0; a < 8; ++a) {
        const double* n = kHexNodes[a];
        d(a, 0) = 0.125 * n[0] * (1 + eta * n[1]) * (1 + ze * n[2]);
        d(a, 1) = 0.125 * n[1] * (1 + xi * n[0]) * (1 + ze * n[2]);
        d(a, 2) = 0.125 * n[2] * (1 + xi * n[0]) * (1 + eta * n[1]);
      }
      return d;
    }
    case ElementType::wedge6: {
      Eigen::MatrixXd d(6, 3);
      const double L[3] = {1 - xi - eta, xi, eta};
      const double dLx[3] = {-1, 1, 0}, dLe[3] = {-1, 0, 1};
      for (int a = 0; a < 6; ++a) {
        const double zf = 0.5 * (1 + ze * kWedgeNodes[a][2]);
        d(a, 0) = dLx[a % 3] * zf;
        d(a, 1) = dLe[a % 3] * zf;
        d(a, 2) = L[a % 3] * 0.5 * kWedgeNodes[a][2];
      }
      return d;
    }
    case ElementType::quad4: {
      Eigen::MatrixXd d(4, 2);
      for (int a = 0; a < 4; ++a) {
        d(a, 0) = 0.25 * kQuadNodes[a][0] * (1 + eta * kQuadNodes[a][1]);
        d(a, 1) = 0.25 * kQuadNodes[a][1] * (1 + xi * kQuadNodes[a][0]);
      }
      return d;
    }
    case ElementType::tri3: {
      Eigen::MatrixXd d(3, 2);
      d << -1, -1, 1, 0, 0, 1;
      return d;
    }
  }
  return {};
}

// Quadrature exact for ∫ ∂N/∂X dV (the cofactors of the Jacobian) on each element type.
std::vector<QuadPoint> quadrature(ElementType t) {
  const double g = 1 / std::sqrt(3.0);
  std::vector<QuadPoint> q;
  switch (t) {
    case ElementType::tet4: q.push_back({{0.25, 0.25, 0.25}, 1.0 / 6}); break;
    case ElementType::hex8:
      for (double a : {-g, g}) for (double b : {-g, g}) for (double c : {-g, g}) q.push_back({{a, b, c}, 1.0});
      break;
    case ElementType::wedge6: {
      const double tp[3][2] = {{1.0 / 6, 1.0 / 6}, {2.0 / 3, 1.0 / 6}, {1.0 / 6, 2.0 / 3}};
      for (auto& p : tp) for (double c : {-g, g}) q.push_back({{p[0], p[1], c}, 1.0 / 6});
      break;
    }
    case ElementType::quad4:
      for (double a : {-g, g}) for (double b : {-g, g}) q.push_back({{a, b, 0}, 1.0});
      break;
    case ElementType::tri3: q.push_back({{1.0 / 3, 1.0 / 3, 0}, 0.5}); break;
  }
  return q;
}

// Hourglass base vectors: nodal values of the non-linear terms of the shape-function basis.
std::vector<std::vector<double>> hourglass_bases(ElementType t) {
  std::vector<std::vector<double>> h;
  if (t == ElementType::hex8) {
    h.assign(4, std::vector<double>(8));
    for (int a = 0; a < 8; ++a) {
      const double* n = kHexNodes[a];
      h[0][a] = n[0] * n[1]; h[1][a] = n[1] * n[2]; h[2][a] = n[2] * n[0]; h[3][a] = n[0] * n[1] * n[2];
    }
  } else if (t == ElementType::wedge6) {
    h.assign(2, std::vector<double>(6));
    for (int a = 0; a < 6; ++a) {
      h[0][a] = kWedgeNodes[a][0] * kWedgeNodes[a][2];
      h[1][a] = kWedgeNodes[a][1] * kWedgeNodes[a][2];
    }
  } else if (t == ElementType::quad4) {
    h.assign(1, std::vector<double>(4));
    for (int a = 0; a < 4; ++a) h[0][a] = kQuadNodes[a][0] * kQuadNodes[a][1];
  }
  return h;
}

}  // namespace

ElementBlock setup_block(const Part& part, int part_index, const Material& mat, const double* X,
                         double hourglass, const std::string& model_name) {
  ElementBlock blk;
  blk.type = part.type;
  blk.part = part_index;
  blk.nn = nodes_per_element(part.type);
  blk.dim = is_membrane(part.type) ? 2 : 3;
  blk.rigid = mat.rigid;
  blk.rho = mat.density;
  blk.E = mat.E;
  blk.nu = mat.nu;
  blk.mu = mat.E / (2 * (1 + mat.nu));
  blk.lambda = mat.E * mat.nu / ((1 + mat.nu) * (1 - 2 * mat.nu));
  blk.kappa = hourglass;
  blk.thickness = is_membrane(part.type) ? part.thickness : 1.0;
  blk.conn = part.conn;
  const auto hb = hourglass_bases(part.type);
  blk.nh = int(hb.size());
  const int nn = blk.nn, d = blk.dim, nh = blk.nh;
  const std::size_t ne = part.size();
  blk.b.assign(ne * nn * d, 0.0);
  blk.gamma.assign(ne * nh * nn, 0.0);
  blk.khg.assign(ne, 0.0);
  blk.vol.assign(ne, 0.0);
  const auto qp = quadrature(part.type);
  std::vector<Eigen::MatrixXd> dN;
  for (const auto& q : qp) dN.push_back(shape_derivatives(part.type, q.xi));
  // An element named by its index within the part cannot be found in gmsh: its centroid can.
  const auto element_at = [&](std::size_t e) {
    Eigen::Vector3d c(0, 0, 0);
    for (int a = 0; a < nn; ++a) c += Eigen::Vector3d(X + 3 * std::size_t(part.conn[e * nn + a])) / nn;
    return "element " + std::to_string(e + 1) + " of the part, centred at " + pipeline::format_position_mm(c.x(), c.y(), c.z());
  };
  for (std::size_t e = 0; e < ne; ++e) {
    // Reference nodal coordinates; membranes in a local orthonormal frame of their plane.
    Eigen::MatrixXd Xe(nn, d);
    if (d == 3) {
      for (int a = 0; a < nn; ++a)
        for (int i = 0; i < 3; ++i) Xe(a, i) = X[3 * std::size_t(part.conn[e * nn + a]) + i];
    } else {
      Eigen::Vector3d P[4], c(0, 0, 0);
      for (int a = 0; a < nn; ++a) {
        P[a] = Eigen::Vector3d(X + 3 * std::size_t(part.conn[e * nn + a]));
        c += P[a] / nn;
      }
      Eigen::Vector3d n = nn == 3 ? (P[1] - P[0]).cross(P[2] - P[0]) : (P[2] - P[0]).cross(P[3] - P[1]);
      if (n.norm() <= 0) throw pipeline::bad_input(model_name, "part '" + part.name + "': " + element_at(e) + " is degenerate (zero area)");
      n.normalize();
      Eigen::Vector3d e1 = (P[1] - P[0]) - n * n.dot(P[1] - P[0]);
      e1.normalize();
      Eigen::Vector3d e2 = n.cross(e1);
      for (int a = 0; a < nn; ++a) { Xe(a, 0) = (P[a] - c).dot(e1); Xe(a, 1) = (P[a] - c).dot(e2); }
    }
    Eigen::MatrixXd bsum = Eigen::MatrixXd::Zero(nn, d);
    double V = 0;
    for (std::size_t k = 0; k < qp.size(); ++k) {
      Eigen::MatrixXd Jm = Xe.transpose() * dN[k];  // d×d, J_ij = ∂X_i/∂ξ_j
      const double det = Jm.determinant();
      if (!(det > 1e-14 * std::pow(Xe.cwiseAbs().maxCoeff() + 1e-300, d)))
        throw pipeline::bad_input(model_name, "part '" + part.name + "': " + element_name(part.type) + " " +
                                                  element_at(e) + ", is inverted or degenerate (Jacobian " +
                                                  pipeline::format_number(det) + ")");
      bsum += dN[k] * Jm.inverse() * (det * qp[k].w);  // ∂N/∂X = ∂N/∂ξ J⁻¹
      V += det * qp[k].w;
    }
    bsum /= V;
    double bb = 0;
    for (int a = 0; a < nn; ++a)
      for (int j = 0; j < d; ++j) {
        blk.b[(e * nn + a) * d + j] = bsum(a, j);
        bb += bsum(a, j) * bsum(a, j);
      }
    blk.vol[e] = V * blk.thickness;
    double gg = 0;
    for (int h = 0; h < nh; ++h) {
      Eigen::VectorXd hv(nn);
      for (int a = 0; a < nn; ++a) hv(a) = hb[h][a];
      Eigen::VectorXd hx = Xe.transpose() * hv;  // d
      Eigen::VectorXd gv = hv - bsum * hx;
      for (int a = 0; a < nn; ++a) blk.gamma[(e * nh + h) * nn + a] = gv(a);
      gg += gv.squaredNorm();
    }
    if (nh > 0) blk.khg[e] = hourglass * blk.mu * blk.vol[e] * bb / (gg / nh);
  }
  return blk;
}


}  // namespace solve::internal
