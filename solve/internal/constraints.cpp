#include "solve/internal/constraints.h"

#include <cmath>
#include <map>
#include <numeric>

#include <Eigen/Dense>

#include "pipeline/error.h"
#include "solve/internal/elements.h"

namespace solve::internal {
namespace {

struct UnionFind {
  std::vector<int> p;
  explicit UnionFind(std::size_t n) : p(n) { std::iota(p.begin(), p.end(), 0); }
  int find(int a) {
    while (p[a] != a) a = p[a] = p[p[a]];
    return a;
  }
  void unite(int a, int b) {
    a = find(a); b = find(b);
    if (a != b) p[std::max(a, b)] = std::min(a, b);
  }
};

// Prescribed velocity of dof d of `node` over the step [t, t+dt] for BC k.
double bc_velocity(const Model& m, int k, int node, int d, double t, double dt, const std::vector<double>& X,
                   const std::vector<double>& x) {
  const NodeBc& b = m.bcs[k];
  switch (b.kind) {
    case BcKind::fixed: return 0.0;
    case BcKind::velocity: return b.curve.at(t + 0.5 * dt);
    case BcKind::displacement: return (X[3 * node + d] + b.curve.at(t + dt) - x[3 * node + d]) / dt;
  }
  return 0.0;
}

}  // namespace

Constraints build_constraints(const Model& m, const std::vector<char>& rigid_node, const std::vector<double>& mass,
                              const std::vector<double>& x) {
  const std::size_t n = m.n_nodes();
  UnionFind uf(n);
  for (const auto& p : m.parts)
    if (m.materials[p.material].rigid)
      for (int id : p.conn) uf.unite(id, p.conn[0]);
  for (const auto& t : m.ties) {
    const auto& a = m.group(t.group_a);
    const auto& b = m.group(t.group_b);
    for (int i : a) {
      int best = -1;
      double bd = 1e300;
      for (int j : b) {  // tie sets are small (strap ends): a direct search is enough
        double d2 = 0;
        for (int k = 0; k < 3; ++k) d2 += (x[3 * i + k] - x[3 * j + k]) * (x[3 * i + k] - x[3 * j + k]);
        if (d2 < bd && j != i) { bd = d2; best = j; }
      }
      // Named by tag and position, with its distance; measured where the run starts, so a stage
      // II whose stage I stopped short (the strap ends not yet at the rim) fails here.
      if (best < 0 || std::sqrt(bd) > t.tolerance)
        throw pipeline::bad_input(
            m.name, "tie '" + t.name + "': node " + std::to_string(m.node_tag(std::size_t(i))) + " of '" + t.group_a +
                        "' at " + pipeline::format_position_mm(x[3 * i], x[3 * i + 1], x[3 * i + 2]) + " is " +
                        (best < 0 ? std::string("alone") : pipeline::format_number(std::sqrt(bd)) + " mm") +
                        " from the nearest node of '" + t.group_b + "', more than the tolerance " +
                        pipeline::format_number(t.tolerance) + " mm" +
                        (m.initial_state.file.empty() ? std::string()
                                                      : " (in the starting state " + m.initial_state.file +
                                                            ": did the run that wrote it reach its end?)"));
      uf.unite(i, best);
    }
  }
  std::vector<int> size(n, 0), rigid_root(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const int r = uf.find(int(i));
    size[r]++;
    if (rigid_node[i]) rigid_root[r] = 1;
  }
  Constraints c;
  c.bc.assign(3 * n, -1);
  std::map<int, int> body_of_root, tie_of_root;
  std::vector<int> body_of(n, -1), tie_of(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    const int r = uf.find(int(i));
    if (rigid_root[r]) {
      auto it = body_of_root.find(r);
      if (it == body_of_root.end()) {
        it = body_of_root.emplace(r, int(c.bodies.size())).first;
        c.bodies.emplace_back();
      }
      c.bodies[it->second].nodes.push_back(int(i));
      c.bodies[it->second].M += mass[i];
      body_of[i] = it->second;
    } else if (size[r] > 1) {
      auto it = tie_of_root.find(r);
      if (it == tie_of_root.end()) {
        it = tie_of_root.emplace(r, int(c.ties.size())).first;
        c.ties.emplace_back();
      }
      c.ties[it->second].nodes.push_back(int(i));
      tie_of[i] = it->second;
    } else {
      c.free_nodes.push_back(int(i));
    }
  }
  // One condition a dof: a later one replaced an earlier without a word, so a "fixed" rim that a
  // prescribed velocity also reached moved, and of two prescribed motions the second won. Two
  // fixes agree (bone parts fixed part by part are one rigid body).
  const auto describe = [&](int k) {
    const NodeBc& b = m.bcs[std::size_t(k)];
    return b.kind == BcKind::fixed ? "fixed by fixed[" + b.group + "]"
                                   : std::string(b.kind == BcKind::velocity ? "a velocity" : "a displacement") +
                                         " by prescribed[" + b.group + "]";
  };
  const auto assign = [&](int& slot, int k, int id, int dof, const char* through) {
    if (slot >= 0 && slot != k && !(m.bcs[std::size_t(slot)].kind == BcKind::fixed && m.bcs[std::size_t(k)].kind == BcKind::fixed))
      throw pipeline::bad_input(m.name, "node " + std::to_string(m.node_tag(std::size_t(id))) + through + ": its " +
                                            std::string(1, "xyz"[dof]) + " is " + describe(slot) + " and " + describe(k) +
                                            ": a dof takes one condition");
    slot = k;
  };
  for (std::size_t k = 0; k < m.bcs.size(); ++k) {
    const NodeBc& b = m.bcs[k];
    for (int id : m.group(b.group)) {
      if (body_of[id] >= 0) {
        RigidBody& rb = c.bodies[body_of[id]];
        assign(rb.bc[b.dof], int(k), id, b.dof, " (of a rigid body)");
        rb.bc_node[b.dof] = id;
        rb.rotation_locked = true;
      } else if (tie_of[id] >= 0) {
        assign(c.ties[tie_of[id]].bc[b.dof], int(k), id, b.dof, " (of a tied set)");
        c.ties[tie_of[id]].bc_node[b.dof] = id;
      } else {
        assign(c.bc[3 * id + b.dof], int(k), id, b.dof, "");
      }
    }
  }
  return c;
}

void init_constraint_velocities(Constraints& c, const std::vector<double>& x, const std::vector<double>& mass,
                                std::vector<double>& v) {
  auto mean_v = [&](const std::vector<int>& nodes) {
    std::array<double, 3> s{0, 0, 0};
    double M = 0;
    for (int i : nodes) {
      for (int d = 0; d < 3; ++d) s[d] += mass[i] * v[3 * i + d];
      M += mass[i];
    }
    for (int d = 0; d < 3; ++d) s[d] = M > 0 ? s[d] / M : 0.0;
    return s;
  };
  for (auto& g : c.ties) {
    auto s = mean_v(g.nodes);
    for (int i : g.nodes) for (int d = 0; d < 3; ++d) v[3 * i + d] = s[d];
  }
  for (auto& b : c.bodies) {
    b.V = mean_v(b.nodes);
    b.w = {0, 0, 0};
    for (int i : b.nodes) for (int d = 0; d < 3; ++d) v[3 * i + d] = b.V[d];
  }
}

void advance(Constraints& c, const Model& m, const std::vector<double>& X, const std::vector<double>& mass,
             const std::vector<double>& fint, const std::vector<double>& fext, const std::vector<double>& fcon,
             double alpha, double t, double dt, std::vector<double>& x, std::vector<double>& v,
             std::vector<double>& reac) {
  const double c1 = 1 - 0.5 * alpha * dt, c2 = 1 / (1 + 0.5 * alpha * dt), cp = 1 + 0.5 * alpha * dt;
  auto force = [&](std::size_t k) { return fint[k] + fext[k] + fcon[k]; };
  // Reaction of a constrained dof: the force that turns v_old into v_new under the scheme.
  auto reaction = [&](int i, int d, double v_old, double v_new) {
    const std::size_t k = 3 * std::size_t(i) + d;
    return mass[i] * (cp * v_new - c1 * v_old) / dt - force(k);
  };
  // 1. Free nodes (the bulk): parallel, independent per node.
  const long nf = long(c.free_nodes.size());
#pragma omp parallel for schedule(static) if (nf > kMinParallel)
  for (long q = 0; q < nf; ++q) {
    const int i = c.free_nodes[q];
    for (int d = 0; d < 3; ++d) {
      const std::size_t k = 3 * std::size_t(i) + d;
      const double vo = v[k];
      double vn = mass[i] > 0 ? c2 * (c1 * vo + dt * force(k) / mass[i]) : 0.0;
      reac[k] = 0;
      if (c.bc[k] >= 0) {
        vn = bc_velocity(m, c.bc[k], i, d, t, dt, X, x);
        reac[k] = reaction(i, d, vo, vn);
      }
      v[k] = vn;
      x[k] += dt * vn;
    }
  }
  // 2. Tie groups: one velocity per group.
  for (auto& g : c.ties) {
    double M = 0, F[3] = {0, 0, 0};
    for (int i : g.nodes) {
      M += mass[i];
      for (int d = 0; d < 3; ++d) F[d] += force(3 * std::size_t(i) + d);
    }
    const int i0 = g.nodes[0];
    for (int d = 0; d < 3; ++d) {
      const double vo = v[3 * i0 + d];
      double vn = M > 0 ? c2 * (c1 * vo + dt * F[d] / M) : 0.0;
      if (g.bc[d] >= 0) vn = bc_velocity(m, g.bc[d], g.bc_node[d], d, t, dt, X, x);
      for (int i : g.nodes) {
        const std::size_t k = 3 * std::size_t(i) + d;
        reac[k] = g.bc[d] >= 0 ? reaction(i, d, v[k], vn) : 0.0;
        v[k] = vn;
        x[k] += dt * vn;
      }
    }
  }
  // 3. Rigid bodies: translation of the mass centre + exact rotation about it.
  for (auto& b : c.bodies) {
    Eigen::Vector3d xc(0, 0, 0), F(0, 0, 0), Mo(0, 0, 0);
    for (int i : b.nodes) xc += mass[i] * Eigen::Vector3d(&x[3 * i]);
    xc /= b.M;
    Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
    for (int i : b.nodes) {
      const Eigen::Vector3d r = Eigen::Vector3d(&x[3 * i]) - xc;
      const Eigen::Vector3d f(force(3 * i), force(3 * i + 1), force(3 * i + 2));
      F += f;
      Mo += r.cross(f);
      I += mass[i] * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
    }
    Eigen::Vector3d V(b.V.data()), w(b.w.data());
    V = c2 * (c1 * V + dt * F / b.M);
    for (int d = 0; d < 3; ++d)
      if (b.bc[d] >= 0) V[d] = bc_velocity(m, b.bc[d], b.bc_node[d], d, t, dt, X, x);
    if (b.rotation_locked) {
      w.setZero();
    } else {
      const Eigen::Vector3d rhs = Mo - w.cross(I * w);
      w = c2 * (c1 * w + dt * I.completeOrthogonalDecomposition().solve(rhs));
    }
    const double ang = w.norm() * dt;
    const Eigen::Matrix3d R =
        ang > 0 ? Eigen::AngleAxisd(ang, w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
    const bool constrained = b.bc[0] >= 0 || b.bc[1] >= 0 || b.bc[2] >= 0;
    for (int i : b.nodes) {
      const Eigen::Vector3d xo(&x[3 * i]);
      const Eigen::Vector3d xn = xc + dt * V + R * (xo - xc);
      for (int d = 0; d < 3; ++d) {
        const std::size_t k = 3 * std::size_t(i) + d;
        const double vn = (xn[d] - xo[d]) / dt;
        reac[k] = constrained ? reaction(i, d, v[k], vn) : 0.0;
        v[k] = vn;
        x[k] = xn[d];
      }
    }
    for (int d = 0; d < 3; ++d) { b.V[d] = V[d]; b.w[d] = w[d]; }
  }
}

std::vector<double> rigid_velocities(const Constraints& c) {
  std::vector<double> r;
  for (const auto& b : c.bodies) {
    r.insert(r.end(), b.V.begin(), b.V.end());
    r.insert(r.end(), b.w.begin(), b.w.end());
  }
  return r;
}

void set_rigid_velocities(Constraints& c, const std::vector<double>& rv) {
  for (std::size_t k = 0; k < c.bodies.size(); ++k)
    for (int d = 0; d < 3; ++d) {
      c.bodies[k].V[d] = rv.size() == 6 * c.bodies.size() ? rv[6 * k + d] : 0.0;
      c.bodies[k].w[d] = rv.size() == 6 * c.bodies.size() ? rv[6 * k + 3 + d] : 0.0;
    }
}

}  // namespace solve::internal
