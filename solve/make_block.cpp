#include "solve/make_block.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "pipeline/error.h"

namespace solve {
namespace {

using V3 = std::array<double, 3>;
V3 sub(const double* a, const double* b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 cross(const V3& a, const V3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void finish_groups(Model& m) {
  for (auto& [name, g] : m.node_groups) {
    std::sort(g.begin(), g.end());
    g.erase(std::unique(g.begin(), g.end()), g.end());
  }
}

}  // namespace

Model make_block(const BlockSpec& s, const Material& mat) {
  if (s.nx < 1 || s.ny < 1 || s.nz < 1 || !(s.jitter >= 0 && s.jitter <= 0.3) ||
      !(s.size[0] > 0 && s.size[1] > 0 && s.size[2] > 0) || is_membrane(s.type))
    throw pipeline::bad_input("make_block", "bad block spec");
  Model m;
  m.name = "block";
  const int NX = s.nx + 1, NY = s.ny + 1, NZ = s.nz + 1;
  const double h[3] = {s.size[0] / s.nx, s.size[1] / s.ny, s.size[2] / s.nz};
  std::mt19937 rng(s.seed);
  std::uniform_real_distribution<double> U(-1, 1);
  auto id = [&](int i, int j, int k) { return i + NX * (j + NY * k); };
  m.X.resize(3 * std::size_t(NX) * NY * NZ);
  for (int k = 0; k < NZ; ++k)
    for (int j = 0; j < NY; ++j)
      for (int i = 0; i < NX; ++i) {
        const int ijk[3] = {i, j, k}, N[3] = {NX, NY, NZ};
        bool interior = true;
        for (int d = 0; d < 3; ++d) interior = interior && ijk[d] > 0 && ijk[d] < N[d] - 1;
        for (int d = 0; d < 3; ++d) {
          double c = s.origin[d] + ijk[d] * h[d];
          if (interior) c += s.jitter * h[d] * U(rng);
          m.X[3 * id(i, j, k) + d] = c;
          if (ijk[d] == 0) m.node_groups[std::string(1, "xyz"[d]) + "min"].push_back(id(i, j, k));
          if (ijk[d] == N[d] - 1) m.node_groups[std::string(1, "xyz"[d]) + "max"].push_back(id(i, j, k));
        }
        m.node_groups["all"].push_back(id(i, j, k));
        m.node_groups[s.part].push_back(id(i, j, k));
      }
  Part p;
  p.name = s.part;
  p.type = s.type;
  p.material = 0;
  const double* X = m.X.data();
  auto vol_sign = [&](int a, int b, int c, int d) {
    return dot(cross(sub(X + 3 * b, X + 3 * a), sub(X + 3 * c, X + 3 * a)), sub(X + 3 * d, X + 3 * a));
  };
  for (int k = 0; k < s.nz; ++k)
    for (int j = 0; j < s.ny; ++j)
      for (int i = 0; i < s.nx; ++i) {
        const int c[8] = {id(i, j, k),         id(i + 1, j, k),         id(i + 1, j + 1, k),     id(i, j + 1, k),
                          id(i, j, k + 1),     id(i + 1, j, k + 1),     id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
        if (s.type == ElementType::hex8) {
          p.conn.insert(p.conn.end(), c, c + 8);
        } else if (s.type == ElementType::wedge6) {
          // alternate the diagonal from cell to cell: a less regular mesh
          const bool alt = (i + j) % 2 == 1;  // same split in every layer: conforming faces
          const int t1[3] = {0, 1, 2}, t2[3] = {0, 2, 3}, t3[3] = {0, 1, 3}, t4[3] = {1, 2, 3};
          for (const int* t : alt ? std::array<const int*, 2>{t3, t4} : std::array<const int*, 2>{t1, t2}) {
            for (int a = 0; a < 3; ++a) p.conn.push_back(c[t[a]]);
            for (int a = 0; a < 3; ++a) p.conn.push_back(c[t[a] + 4]);
          }
        } else {
          // Kuhn subdivision: 6 tets along the main diagonal 0 → 6, conforming between cells
          const int paths[6][2] = {{1, 2}, {1, 5}, {3, 2}, {3, 7}, {4, 5}, {4, 7}};
          for (auto& pp : paths) {
            int t[4] = {c[0], c[pp[0]], c[pp[1]], c[6]};
            if (vol_sign(t[0], t[1], t[2], t[3]) < 0) std::swap(t[2], t[3]);
            p.conn.insert(p.conn.end(), t, t + 4);
          }
        }
      }
  m.parts.push_back(p);
  Material mm = mat;
  if (mm.name.empty()) mm.name = "material";
  m.materials.push_back(mm);
  // Boundary surfaces, outward.
  auto add_face = [&](const std::string& g, int a, int b, int cc, int d, const V3& out) {
    for (auto t : {std::array<int, 3>{a, b, cc}, std::array<int, 3>{a, cc, d}}) {
      if (dot(cross(sub(X + 3 * t[1], X + 3 * t[0]), sub(X + 3 * t[2], X + 3 * t[0])), out) < 0) std::swap(t[1], t[2]);
      m.surfaces[g].push_back(t);
    }
  };
  for (int k = 0; k < s.nz; ++k)
    for (int j = 0; j < s.ny; ++j) {
      add_face("xmin", id(0, j, k), id(0, j + 1, k), id(0, j + 1, k + 1), id(0, j, k + 1), {-1, 0, 0});
      add_face("xmax", id(s.nx, j, k), id(s.nx, j + 1, k), id(s.nx, j + 1, k + 1), id(s.nx, j, k + 1), {1, 0, 0});
    }
  for (int k = 0; k < s.nz; ++k)
    for (int i = 0; i < s.nx; ++i) {
      add_face("ymin", id(i, 0, k), id(i + 1, 0, k), id(i + 1, 0, k + 1), id(i, 0, k + 1), {0, -1, 0});
      add_face("ymax", id(i, s.ny, k), id(i + 1, s.ny, k), id(i + 1, s.ny, k + 1), id(i, s.ny, k + 1), {0, 1, 0});
    }
  for (int j = 0; j < s.ny; ++j)
    for (int i = 0; i < s.nx; ++i) {
      add_face("zmin", id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0), id(i, j + 1, 0), {0, 0, -1});
      add_face("zmax", id(i, j, s.nz), id(i + 1, j, s.nz), id(i + 1, j + 1, s.nz), id(i, j + 1, s.nz), {0, 0, 1});
    }
  for (std::size_t i = 0; i < m.n_nodes(); ++i) m.node_tags.push_back(long(i + 1));
  m.control.end_time = 1.0;
  finish_groups(m);
  return m;
}

Model make_plate(const PlateSpec& s, const Material& mat) {
  if (s.nx < 1 || s.ny < 1 || !is_membrane(s.type) || !(s.thickness > 0) || !(s.jitter >= 0 && s.jitter <= 0.3))
    throw pipeline::bad_input("make_plate", "bad plate spec");
  Model m;
  m.name = "plate";
  const int NX = s.nx + 1, NY = s.ny + 1;
  const double h[2] = {s.size[0] / s.nx, s.size[1] / s.ny};
  std::mt19937 rng(s.seed);
  std::uniform_real_distribution<double> U(-1, 1);
  auto id = [&](int i, int j) { return i + NX * j; };
  m.X.resize(3 * std::size_t(NX) * NY);
  for (int j = 0; j < NY; ++j)
    for (int i = 0; i < NX; ++i) {
      const bool interior = i > 0 && i < NX - 1 && j > 0 && j < NY - 1;
      const int n = id(i, j);
      m.X[3 * n] = s.origin[0] + i * h[0] + (interior ? s.jitter * h[0] * U(rng) : 0);
      m.X[3 * n + 1] = s.origin[1] + j * h[1] + (interior ? s.jitter * h[1] * U(rng) : 0);
      m.X[3 * n + 2] = s.origin[2];
      if (i == 0) m.node_groups["xmin"].push_back(n);
      if (i == NX - 1) m.node_groups["xmax"].push_back(n);
      if (j == 0) m.node_groups["ymin"].push_back(n);
      if (j == NY - 1) m.node_groups["ymax"].push_back(n);
      m.node_groups["all"].push_back(n);
      m.node_groups[s.part].push_back(n);
    }
  Part p;
  p.name = s.part;
  p.type = s.type;
  p.material = 0;
  p.thickness = s.thickness;
  for (int j = 0; j < s.ny; ++j)
    for (int i = 0; i < s.nx; ++i) {
      const int c[4] = {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
      if (s.type == ElementType::quad4) {
        p.conn.insert(p.conn.end(), c, c + 4);
      } else {
        p.conn.insert(p.conn.end(), {c[0], c[1], c[2], c[0], c[2], c[3]});
      }
      std::array<int, 3> t1{c[0], c[1], c[2]}, t2{c[0], c[2], c[3]};
      m.surfaces[s.part].push_back(t1);
      m.surfaces[s.part].push_back(t2);
    }
  m.parts.push_back(p);
  Material mm = mat;
  if (mm.name.empty()) mm.name = "material";
  m.materials.push_back(mm);
  for (std::size_t i = 0; i < m.n_nodes(); ++i) m.node_tags.push_back(long(i + 1));
  m.control.end_time = 1.0;
  finish_groups(m);
  return m;
}

void append_model(Model& dst, const Model& src, const std::string& prefix) {
  const int off = int(dst.n_nodes());
  const int moff = int(dst.materials.size());
  long tag_off = 0;
  for (long t : dst.node_tags) tag_off = std::max(tag_off, t);
  dst.X.insert(dst.X.end(), src.X.begin(), src.X.end());
  for (std::size_t i = 0; i < src.n_nodes(); ++i)
    dst.node_tags.push_back(tag_off + (src.node_tags.empty() ? long(i + 1) : src.node_tags[i]));
  for (auto mat : src.materials) {
    mat.name = prefix + mat.name;
    dst.materials.push_back(mat);
  }
  for (auto p : src.parts) {
    p.name = prefix + p.name;
    p.material += moff;
    for (int& id : p.conn) id += off;
    dst.parts.push_back(std::move(p));
  }
  for (const auto& [name, g] : src.node_groups) {
    auto& d = dst.node_groups[prefix + name];
    for (int id : g) d.push_back(id + off);
  }
  for (const auto& [name, tris] : src.surfaces) {
    auto& d = dst.surfaces[prefix + name];
    for (auto t : tris) d.push_back({t[0] + off, t[1] + off, t[2] + off});
  }
  for (auto b : src.bcs) { b.group = prefix + b.group; dst.bcs.push_back(b); }
  for (auto l : src.loads) { l.group = prefix + l.group; dst.loads.push_back(l); }
  for (auto iv : src.initial_velocities) { iv.group = prefix + iv.group; dst.initial_velocities.push_back(iv); }
  for (auto t : src.ties) { t.group_a = prefix + t.group_a; t.group_b = prefix + t.group_b; dst.ties.push_back(t); }
  for (auto c : src.contacts) { c.slave = prefix + c.slave; c.master = prefix + c.master; dst.contacts.push_back(c); }
  finish_groups(dst);
}

}  // namespace solve
