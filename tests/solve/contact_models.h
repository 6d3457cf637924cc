#pragma once
// Models shared by the contact verification tests (tests/solve/contact_*_test.cpp): graded
// structured blocks (solver-core's make_block with its node planes moved) and rigid triangulated
// surfaces. Test helpers only.
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "solve/make_block.h"
#include "solve/model.h"

namespace contact_test {

/// Plane positions 0 … length: cells of size h0 up to `fine`, then growing by `ratio` per cell
/// (the growing part scaled to end exactly at `length`).
inline std::vector<double> graded(double h0, double fine, double length, double ratio) {
  std::vector<double> c{0};
  const int n_fine = std::max(1, int(std::lround(fine / h0)));
  for (int i = 1; i <= n_fine; ++i) c.push_back(i * fine / n_fine);
  std::vector<double> grow;
  double h = fine / n_fine, sum = 0;
  while (sum < length - fine) {
    h *= ratio;
    grow.push_back(h);
    sum += h;
  }
  const double scale = (length - fine) / sum;
  for (double g : grow) c.push_back(c.back() + g * scale);
  return c;
}

/// Hex block with the given plane positions per axis (each ascending); groups as make_block's
/// ("xmin" … "zmax" node groups and outward surfaces, "all", the part name).
inline solve::Model graded_block(const std::vector<double>& xs, const std::vector<double>& ys,
                                 const std::vector<double>& zs, const solve::Material& mat,
                                 const std::string& part = "block") {
  solve::BlockSpec spec;
  spec.nx = int(xs.size()) - 1;
  spec.ny = int(ys.size()) - 1;
  spec.nz = int(zs.size()) - 1;
  spec.size = {1, 1, 1};
  spec.part = part;
  solve::Model m = solve::make_block(spec, mat);
  const std::vector<double>* planes[3] = {&xs, &ys, &zs};
  const int n[3] = {spec.nx, spec.ny, spec.nz};
  for (std::size_t i = 0; i < m.n_nodes(); ++i)
    for (int d = 0; d < 3; ++d) {
      const long k = std::lround(m.X[3 * i + d] * n[d]);  // make_block put plane k at k / n
      m.X[3 * i + d] = (*planes[d])[std::size_t(k)];
    }
  return m;
}

/// A rigid triangulated surface y = height(x, z) over the grid xs × zs, cells kept where
/// keep(x, z) holds at all four corners; outward normal toward −y (facing a body below it).
inline solve::Model rigid_surface(const std::vector<double>& xs, const std::vector<double>& zs,
                                  const std::function<double(double, double)>& height,
                                  const std::function<bool(double, double)>& keep, const std::string& name,
                                  double density = 1e-2) {
  solve::Model m;
  m.name = name;
  solve::Material mat;
  mat.name = name;
  mat.density = density;
  mat.E = 1000;
  mat.nu = 0.3;
  mat.rigid = true;
  m.materials.push_back(mat);
  const int nx = int(xs.size()), nz = int(zs.size());
  std::vector<int> id(std::size_t(nx * nz), -1);
  auto node = [&](int i, int k) {
    int& v = id[std::size_t(i + nx * k)];
    if (v < 0) {
      v = int(m.n_nodes());
      m.X.insert(m.X.end(), {xs[std::size_t(i)], height(xs[std::size_t(i)], zs[std::size_t(k)]), zs[std::size_t(k)]});
      m.node_groups[name].push_back(v);
    }
    return v;
  };
  solve::Part p;
  p.name = name;
  p.type = solve::ElementType::tri3;
  p.material = 0;
  p.thickness = 1;
  auto& tris = m.surfaces[name];
  for (int k = 0; k + 1 < nz; ++k)
    for (int i = 0; i + 1 < nx; ++i) {
      const double x0 = xs[std::size_t(i)], x1 = xs[std::size_t(i + 1)], z0 = zs[std::size_t(k)], z1 = zs[std::size_t(k + 1)];
      if (!(keep(x0, z0) && keep(x1, z0) && keep(x1, z1) && keep(x0, z1))) continue;
      const int a = node(i, k), b = node(i + 1, k), c = node(i + 1, k + 1), d = node(i, k + 1);
      tris.push_back({a, b, c});  // (b − a) × (c − a) ∥ x̂ × ẑ = −ŷ
      tris.push_back({a, c, d});
      p.conn.insert(p.conn.end(), {a, b, c, a, c, d});
    }
  m.parts.push_back(p);
  std::sort(m.node_groups[name].begin(), m.node_groups[name].end());
  return m;
}

}  // namespace contact_test
