#pragma once
/// Element kernels of the explicit solver (internal to solve/).
///
/// Formulation (why): every element is a total-Lagrangian *uniform-strain* element in the sense
/// of Flanagan & Belytschko (1981): the deformation gradient is the element mean
///   F = Σ_a x_a ⊗ b_a,   b_a = (1/V0) ∫ ∂N_a/∂X dV   (exact quadrature, computed once),
/// so a uniform strain field is reproduced exactly on any shape (patch test), the volumetric
/// part is one constant per element (mean dilatation: no volumetric locking at ν = 0.48), and a
/// rigid rotation gives F = R, hence zero stress (objective). The non-linear modes left free by
/// the single point (hex: 4, wedge: 2, quad: 1 per direction) are held by a stiffness-type
/// hourglass control f_a = -k γ_a q, q = Σ_a γ_a x_a, with γ orthogonal to every affine field,
/// so it is zero for uniform strain and for rigid motion; its energy ½k|q|² is part of the
/// internal energy. Solids: compressible neo-Hookean
///   W = μ/2 (tr FᵀF − 3) − μ ln J + λ/2 (ln J)²,  P = μ (F − F⁻ᵀ) + λ ln J F⁻ᵀ
/// (reduces to linear elasticity with E, ν for small strain; does not soften in compression
/// like St.Venant–Kirchhoff, see DESIGN.md pitfalls). Membranes (straps, loaded in tension):
/// St.Venant–Kirchhoff plane stress on the mean surface deformation; no bending stiffness.
/// A one-point element costs ~1/6 of a fully integrated wedge, which is what makes the
/// throughput target (≥ 5 M wedge updates/s/core) reachable.
#include <vector>

#include "solve/model.h"

namespace solve::internal {

/// Loops shorter than this run on one thread: on small models the fork/join cost of an OpenMP
/// region exceeds the work, and on a loaded machine waiting at the barrier for a descheduled
/// thread costs a scheduler time slice per region (measured: 3,468 wedges, load 7 on 2 cores:
/// 0.9 s on one thread, 43 s on two). 16,384 wedges take ~1.5 ms per loop on one core.
constexpr long kMinParallel = 16384;

struct ElementBlock {
  ElementType type = ElementType::wedge6;
  int part = -1;
  int nn = 0, nh = 0, dim = 3;     ///< nodes, hourglass vectors, dimension of b (3 solids, 2 membranes)
  bool rigid = false;
  double rho = 0, mu = 0, lambda = 0, E = 0, nu = 0, thickness = 1, kappa = 0;
  std::vector<int> conn;           ///< #e×nn
  std::vector<double> b;           ///< #e×nn×dim mean shape-function gradients [1/mm]
  std::vector<double> gamma;       ///< #e×nh×nn hourglass vectors
  std::vector<double> khg;         ///< #e hourglass stiffness [N/mm]
  std::vector<double> vol;         ///< #e reference volume (membranes: area × thickness) [mm³]
  std::size_t force_offset = 0;    ///< start of this block's #e×nn×3 slice in the element-force array
  std::size_t size() const { return vol.size(); }
};

/// Precomputes b, γ, volumes for a part. Throws pipeline::Error(bad_input) naming the part and
/// element if an element is degenerate or inverted (non-positive Jacobian at a quadrature point).
ElementBlock setup_block(const Part& part, int part_index, const Material& mat, const double* X,
                         double hourglass, const std::string& model_name);

/// Internal nodal forces of every element, written (not added) to fe[force_offset + e*nn*3 + a*3 + i] [N].
/// @return number of elements with J ≤ 0 (inverted) in the current state (0 when healthy).
/// OpenMP-parallel over elements; no shared writes.
int forces_for_elems(const ElementBlock& blk, const double* x, double* fe);

/// Strain + hourglass energy of the block in state x [N·mm].
double energy_for_elems(const ElementBlock& blk, const double* x);

/// Von Mises stress of the Cauchy stress per element [MPa], written to vm[e].
void von_mises_for_elems(const ElementBlock& blk, const double* x, double* vm);

/// Stable time step bound of the block (min over elements of 2/ω_max, ω_max from a Gershgorin-type
/// bound of the element stiffness over the lumped mass) in state x [ms]; +inf for rigid blocks.
/// `mass_factor` (#e, or empty) multiplies element mass (mass scaling). Elements with
/// `skip[e]` != 0 (`skip` #e, or null) are left out: +inf if every element is.
double stable_dt_for_elems(const ElementBlock& blk, const double* x, const std::vector<double>& mass_factor,
                           const std::vector<char>* skip = nullptr);

/// Per-element stable step in the reference state (for mass scaling), #e [ms].
std::vector<double> element_dt(const ElementBlock& blk, const double* X);

}  // namespace solve::internal
