#include "solve/solver.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

#include "pipeline/error.h"
#include "solve/internal/constraints.h"
#include "solve/internal/elements.h"

namespace solve {

using internal::ElementBlock;
using internal::kMinParallel;

struct Solver::Impl {
  Model m;
  std::size_t n = 0;
  std::vector<ElementBlock> blocks;
  std::vector<std::vector<double>> mass_factor;  // per block, per element (empty: 1)
  std::vector<double> fe;                        // element forces, all blocks
  std::vector<long> node_ptr, node_inc;          // CSR node → indices into fe (first of 3)
  std::vector<double> X, x, v, v_old, mass, fint, fext, fcon, reac;
  internal::Constraints con;
  std::vector<ContactPair> pairs;
  double time = 0, dt = 0, dt_stable = 0, added = 0;
  // The step the contact stiffness k = s·m*/Δt² is set with: dt_scale times the stable step of
  // every element, held or not (contact.cpp). Equal to dt unless held elements are left out.
  double dt_contact = 0;
  // Per block, per element: every node held by `fixed` in x, y and z (empty: none is). Such an
  // element cannot deform, so it does not bound the step: stage I holds the head and the
  // respirator while only the straps move, and their elements had set its step (0.0046 ms
  // against the straps' 0.018 ms).
  std::vector<std::vector<char>> held;
  std::string step_part;  // the part whose element sets the starting stable step ("" if none)
  double physical = 0;  // summed apart: total − added loses it when added is 1e15 times larger
  long step = 0;
  Energies en;  // time and kinetic of the last step, the rest of the last that requested them
  // Works of the steps done so far [mJ]: absorbed by contact and by damping, done by loads and
  // prescribed / fixed dofs.
  double w_contact = 0, w_damping = 0, w_external = 0;
  double e_initial = 0;
  bool e_initial_set = false;

  /// Stable steps of the elements in the current state [ms]: of those not held, and of all. A
  /// block without held elements is passed over once for both (the update runs every
  /// dt_update_interval steps, and stage II holds only its bones).
  struct StableSteps {
    double free, every;
  };
  StableSteps compute_stable_dt() const {
    StableSteps d{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    for (std::size_t k = 0; k < blocks.size(); ++k) {
      const double all = internal::stable_dt_for_elems(blocks[k], x.data(), mass_factor[k]);
      d.every = std::min(d.every, all);
      d.free = std::min(d.free, held[k].empty() ? all
                                                : internal::stable_dt_for_elems(blocks[k], x.data(), mass_factor[k], &held[k]));
    }
    return d;
  }
  /// The step from the stable steps of the elements not held (free) and of all (every) [ms], as
  /// dt_scale times the free one, but no longer than lets every contact pair's penalty
  /// oscillator, ω = √s / dt_contact, keep ω·Δt ≤ √(1 + ξ²) − ξ: half the central-difference
  /// limit 2(√(1 + ξ²) − ξ) with damping ratio ξ, and ω·Δt ≤ 1 undamped, as the penalty alone
  /// gives at Δt = dt_contact for s ≤ 1 (contact.cpp). The contact stiffness keeps the step of
  /// every element, held or not, so a stage that holds the head (stage I) presses as hard as the
  /// next one that frees it: a stiffness from the longer step was 16 times softer in stage I,
  /// and stage II then began with a 318.6 N jump of the bottom strap's contact force on stage
  /// I's penetrations (31.8 N at its end; solve/README.md).
  /// The model's initial velocities on their groups, tied and rigid nodes then made consistent.
  void apply_initial_velocities() {
    for (const auto& iv : m.initial_velocities)
      for (int id : m.group(iv.group))
        for (int i = 0; i < 3; ++i) v[3 * id + i] = iv.v[i];
    internal::init_constraint_velocities(con, x, mass, v);
  }
  void choose_step(double stable_free, double stable_every) {
    dt_stable = std::isfinite(stable_free) ? stable_free : stable_every;
    dt_contact = m.control.dt_scale * stable_every;
    double dt_max = std::numeric_limits<double>::infinity();
    for (const auto& c : pairs) {
      const double s_pen = c.spec().penalty_scale, xi = c.spec().damping_ratio;
      if (s_pen > 0) dt_max = std::min(dt_max, dt_contact * (std::sqrt(1 + xi * xi) - xi) / std::sqrt(s_pen));
    }
    dt = std::min(m.control.dt_scale * stable_free, std::max(dt_contact, dt_max));
    // Every deformable element held and no contact: nothing else bounds the step; keep theirs.
    if (!std::isfinite(dt)) dt = dt_contact;
  }
  double internal_energy() const {
    double w = 0;
    for (const auto& b : blocks)
      if (!b.rigid) w += internal::energy_for_elems(b, x.data());
    return w;
  }
};

Solver::Solver(Model model, const std::vector<double>* start_x) : p_(std::make_unique<Impl>()) {
  check_model(model);
  Impl& s = *p_;
  s.m = std::move(model);
  const Model& m = s.m;
  s.n = m.n_nodes();
  s.X = m.X;
  s.x = m.X;
  s.v.assign(3 * s.n, 0.0);
  s.mass.assign(s.n, 0.0);
  // 1. Elements, masses (with optional mass scaling to control.dt_target), held elements.
  std::vector<char> fixed_dofs(s.n, 0);  // bit d: dof d held by `fixed`
  for (const auto& bc : m.bcs)
    if (bc.kind == BcKind::fixed)
      for (int id : m.group(bc.group)) fixed_dofs[std::size_t(id)] |= char(1 << bc.dof);
  std::size_t off = 0;
  double dt_free = std::numeric_limits<double>::infinity(), dt_every = dt_free;
  for (std::size_t k = 0; k < m.parts.size(); ++k) {
    const Part& part = m.parts[k];
    ElementBlock b = internal::setup_block(part, int(k), m.materials[part.material], m.X.data(),
                                           m.control.hourglass, m.name);
    b.force_offset = off;
    off += b.size() * b.nn * 3;
    std::vector<char> held;
    if (!b.rigid) {
      held.assign(b.size(), 0);
      bool any = false;
      for (std::size_t e = 0; e < b.size(); ++e) {
        bool all = true;
        for (int a = 0; a < b.nn && all; ++a) all = fixed_dofs[std::size_t(b.conn[e * b.nn + a])] == 7;
        held[e] = char(all);
        any = any || all;
      }
      if (!any) held.clear();
    }
    const auto is_held = [&](std::size_t e) { return !held.empty() && held[e]; };
    std::vector<double> edt = internal::element_dt(b, m.X.data());
    std::vector<double> factor;
    if (m.control.dt_target > 0 && !b.rigid) {
      factor.assign(b.size(), 1.0);
      for (std::size_t e = 0; e < b.size(); ++e) {
        const double ok = m.control.dt_scale * edt[e];
        if (ok < m.control.dt_target && !is_held(e)) factor[e] = (m.control.dt_target / ok) * (m.control.dt_target / ok);
      }
    }
    for (std::size_t e = 0; e < b.size(); ++e) {
      const double me = b.rho * b.vol[e];
      const double f = factor.empty() ? 1.0 : factor[e];
      s.added += me * (f - 1);
      s.physical += me;
      for (int a = 0; a < b.nn; ++a) s.mass[b.conn[e * b.nn + a]] += me * f / b.nn;
      const double dt_e = edt[e] * std::sqrt(f);
      dt_every = std::min(dt_every, dt_e);
      if (dt_e < dt_free && !is_held(e)) dt_free = dt_e, s.step_part = part.name;
    }
    s.blocks.push_back(std::move(b));
    s.mass_factor.push_back(std::move(factor));
    s.held.push_back(std::move(held));
  }
  s.fe.assign(off, 0.0);
  // 2. Node → element-force incidences (fixed order: block, element, local node).
  s.node_ptr.assign(s.n + 1, 0);
  for (const auto& b : s.blocks)
    if (!b.rigid)
      for (int id : b.conn) s.node_ptr[id + 1]++;
  for (std::size_t i = 0; i < s.n; ++i) s.node_ptr[i + 1] += s.node_ptr[i];
  s.node_inc.assign(s.node_ptr[s.n], 0);
  std::vector<long> fill(s.node_ptr.begin(), s.node_ptr.end() - 1);
  for (const auto& b : s.blocks)
    if (!b.rigid)
      for (std::size_t k = 0; k < b.conn.size(); ++k)
        s.node_inc[fill[b.conn[k]]++] = long(b.force_offset + 3 * k);
  s.fint.assign(3 * s.n, 0.0);
  s.fext.assign(3 * s.n, 0.0);
  s.fcon.assign(3 * s.n, 0.0);
  s.reac.assign(3 * s.n, 0.0);
  // 3. Constraints: ties (matched where the run starts), rigid bodies, boundary conditions.
  if (start_x && start_x->size() != s.x.size())
    throw pipeline::bad_input(m.name, "restart state has " + std::to_string(start_x->size() / 3) +
                                          " nodes, the model has " + std::to_string(s.n));
  std::vector<char> rigid_node(s.n, 0);
  for (const auto& b : s.blocks)
    if (b.rigid)
      for (int id : b.conn) rigid_node[id] = 1;
  s.con = internal::build_constraints(m, rigid_node, s.mass, start_x ? *start_x : s.x);
  // 4. Initial velocities.
  s.apply_initial_velocities();
  // 5. Contact pairs.
  for (const auto& c : m.contacts) {
    ContactSpec spec;
    spec.name = c.name;
    spec.slave_nodes = m.group(c.slave);
    spec.master_tris = m.surface(c.master);
    // A slave group that is a surface (2D elements, or the boundary of 3D ones) is integrated
    // over its facets (segment-to-surface, contact.h); a node group stays node-to-surface.
    if (auto it = m.surfaces.find(c.slave); it != m.surfaces.end()) spec.slave_tris = it->second;
    spec.penalty_scale = c.penalty_scale;
    spec.damping_ratio = c.damping_ratio;
    spec.friction = c.friction;
    spec.two_sided = c.two_sided;
    s.pairs.emplace_back(std::move(spec), s.n);
  }
  // 6. The step.
  if (!std::isfinite(dt_every)) {
    // only rigid parts: the step is bounded by contact / loads; take the target or 1e-3 ms
    s.dt_stable = m.control.dt_target > 0 ? m.control.dt_target : 1e-3;
    s.dt = s.dt_contact = m.control.dt_target > 0 ? m.control.dt_target : m.control.dt_scale * s.dt_stable;
  } else if (m.control.dt_target > 0) {
    s.dt_stable = std::isfinite(dt_free) ? dt_free : dt_every;
    s.dt = s.dt_contact = m.control.dt_target;
  } else {
    s.choose_step(dt_free, dt_every);
  }
}

Solver::~Solver() = default;

void Solver::step() {
  Impl& s = *p_;
  const Model& m = s.m;
  const std::size_t n = s.n;
  const double dt = s.dt, t = s.time;
  // 1. Internal forces: per element, then gathered per node in a fixed order.
  int inverted = 0;
  for (const auto& b : s.blocks)
    if (!b.rigid) inverted += internal::forces_for_elems(b, s.x.data(), s.fe.data());
  const long nl = long(n);
#pragma omp parallel for schedule(static) if (nl > kMinParallel)
  for (long i = 0; i < nl; ++i) {
    double f0 = 0, f1 = 0, f2 = 0;
    for (long k = s.node_ptr[i]; k < s.node_ptr[i + 1]; ++k) {
      const double* f = &s.fe[s.node_inc[k]];
      f0 += f[0]; f1 += f[1]; f2 += f[2];
    }
    s.fint[3 * i] = f0; s.fint[3 * i + 1] = f1; s.fint[3 * i + 2] = f2;
  }
  // 2. Loads and contact.
  std::fill(s.fext.begin(), s.fext.end(), 0.0);
  for (const auto& l : m.loads) {
    const auto& g = m.group(l.group);
    const double f = l.curve.at(t) / double(g.size());
    for (int id : g) s.fext[3 * id + l.dof] += f;
  }
  std::fill(s.fcon.begin(), s.fcon.end(), 0.0);
  double pen = 0;
  const ContactPair* deepest = nullptr;
  for (auto& c : s.pairs) {
    c.add_forces(s.x.data(), s.v.data(), s.mass.data(), dt, s.dt_contact, s.fcon.data());
    if (c.max_penetration() > pen) {
      pen = c.max_penetration();
      deepest = &c;
    }
  }
  const double e_int_n = want_energy_ ? s.internal_energy() : 0.0;
  // 3. Velocities and positions (constraints inside), energy bookkeeping.
  s.v_old = s.v;
  const std::vector<double>& v_old = s.v_old;
  internal::advance(s.con, m, s.X, s.mass, s.fint, s.fext, s.fcon, m.control.damping_alpha, t, dt, s.x, s.v,
                    s.reac);
  double ke = 0, wc = 0, wd = 0, we = 0;
  const double alpha = m.control.damping_alpha;
  bool finite = true;
#pragma omp parallel for schedule(static) if (nl > kMinParallel) reduction(+ : ke, wc, wd, we) reduction(&& : finite)
  for (long i = 0; i < nl; ++i) {
    for (int d = 0; d < 3; ++d) {
      const std::size_t k = 3 * std::size_t(i) + d;
      const double va = 0.5 * (v_old[k] + s.v[k]);
      ke += 0.25 * s.mass[i] * (v_old[k] * v_old[k] + s.v[k] * s.v[k]);
      wc += s.fcon[k] * va * dt;
      wd += alpha * s.mass[i] * va * va * dt;
      we += (s.fext[k] + s.reac[k]) * va * dt;
      finite = finite && std::isfinite(s.x[k]) && std::isfinite(s.v[k]);
    }
  }
  s.en.time = t;
  s.en.kinetic = ke;
  if (want_energy_) {
    // Energies at t_n: the works are centred (f_n · (x_{n+1} − x_{n−1})/2, half of this step's
    // increment before t_n) and the kinetic energy is the mean of the two half-step ones. The
    // balance adds the central-difference scheme's own term −¼·dt·f_int,n·Δv_n (Δv = v_{n+½} −
    // v_{n−½}), O(dt²) while the motion is smooth. With it, the works of loads, reactions,
    // contact and damping cancel the kinetic energy's change exactly, whatever they do, jumps
    // included; what is left is the trapezoid rule's error on the strain energy, zero for a
    // quadratic one (small strains) at a constant step, so the balance error measures the
    // nonlinear response and the step changes (for free vibration the sum is
    // ½ v_{n−½}·M·v_{n+½} + U, the scheme's invariant). The kinetic energy at the mean velocity
    // without that term, as until 2026-12-05, was off by m·Δv²/8 at a velocity jump: a
    // prescribed curve starting at a non-zero slope left the balance off by that for good, and
    // solve stopped the medium_onesize stage-1 run as diverged at step 3 when it was checked at
    // every step.
    // (its own pass, on these steps only: the loop above runs every step and needs no f_int)
    double fint_dv = 0;
#pragma omp parallel for schedule(static) if (nl > kMinParallel) reduction(+ : fint_dv)
    for (long i = 0; i < nl; ++i)
      for (int d = 0; d < 3; ++d) {
        const std::size_t k = 3 * std::size_t(i) + d;
        fint_dv += s.fint[k] * (s.v[k] - v_old[k]);
      }
    s.en.internal = e_int_n;
    s.en.contact = s.w_contact - 0.5 * wc;
    s.en.damping = s.w_damping + 0.5 * wd;
    s.en.external = s.w_external + 0.5 * we;
    s.en.scheme = -0.25 * dt * fint_dv;
    const double total =
        s.en.kinetic + s.en.internal + s.en.contact + s.en.damping - s.en.external + s.en.scheme;
    if (!s.e_initial_set) { s.e_initial = total; s.e_initial_set = true; }
    s.en.balance = total - s.e_initial;
    want_energy_ = false;
  }
  s.w_contact -= wc;
  s.w_damping += wd;
  s.w_external += we;
  s.time += dt;
  s.step++;
  // 4. Health and the periodic update of the stable step.
  if (!finite) health_ = "non-finite position or velocity (NaN/Inf)";
  else if (inverted > 0) health_ = std::to_string(inverted) + " element(s) inverted (J <= 0)";
  else if (pen > m.control.penetration_tolerance) {
    // Name the pair and the place: on a full model a depth alone does not say what went through what.
    const auto q = deepest->deepest_point();
    char xyz[80];
    std::snprintf(xyz, sizeof xyz, "%.2f %.2f %.2f", q[0], q[1], q[2]);
    health_ = "contact penetration " + std::to_string(pen) + " mm deeper than the tolerance " +
              std::to_string(m.control.penetration_tolerance) + " mm (pair '" + deepest->spec().name +
              "', slave point at " + xyz + " mm)";
  }
  if (m.control.dt_target <= 0 && s.step % m.control.dt_update_interval == 0 && health_.empty()) {
    const auto d = s.compute_stable_dt();  // every = +inf when only rigid parts: keep the step
    if (std::isfinite(d.every)) s.choose_step(d.free, d.every);
  }
}

void Solver::run_until(double t) {
  while (p_->time < t && health_.empty()) step();
}

const Model& Solver::model() const { return p_->m; }
double Solver::time() const { return p_->time; }
double Solver::dt() const { return p_->dt; }
long Solver::steps() const { return p_->step; }
double Solver::stable_dt() const { return p_->dt_stable; }
double Solver::contact_dt() const { return p_->dt_contact; }
const std::string& Solver::step_limiting_part() const { return p_->step_part; }
double Solver::added_mass() const { return p_->added; }
double Solver::physical_mass() const { return p_->physical; }
double Solver::total_mass() const { return std::accumulate(p_->mass.begin(), p_->mass.end(), 0.0); }
const std::vector<double>& Solver::x() const { return p_->x; }
const std::vector<double>& Solver::v() const { return p_->v; }
const std::vector<double>& Solver::mass() const { return p_->mass; }
const std::vector<double>& Solver::internal_force() const { return p_->fint; }
const Energies& Solver::energies() const { return p_->en; }
double Solver::internal_energy() const { return p_->internal_energy(); }
const std::vector<ContactPair>& Solver::contacts() const { return p_->pairs; }

std::vector<double> Solver::displacement() const {
  std::vector<double> u(p_->x.size());
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = p_->x[k] - p_->X[k];
  return u;
}

std::vector<double> Solver::von_mises() const {
  const Impl& s = *p_;
  std::vector<double> num(s.n, 0.0), den(s.n, 0.0);
  for (const auto& b : s.blocks) {
    if (b.rigid) continue;
    std::vector<double> vm(b.size());
    internal::von_mises_for_elems(b, s.x.data(), vm.data());
    for (std::size_t e = 0; e < b.size(); ++e)
      for (int a = 0; a < b.nn; ++a) {
        num[b.conn[e * b.nn + a]] += vm[e] * b.vol[e];
        den[b.conn[e * b.nn + a]] += b.vol[e];
      }
  }
  for (std::size_t i = 0; i < s.n; ++i) num[i] = den[i] > 0 ? num[i] / den[i] : 0.0;
  return num;
}

std::vector<double> Solver::contact_pressure() const {
  std::vector<double> p(p_->n, 0.0);
  for (const auto& c : p_->pairs)
    for (std::size_t i = 0; i < p.size(); ++i) p[i] += c.pressure()[i];
  return p;
}

std::vector<double> Solver::contact_shear() const {
  std::vector<double> p(p_->n, 0.0);
  for (const auto& c : p_->pairs)
    for (std::size_t i = 0; i < p.size(); ++i) p[i] += c.shear()[i];
  return p;
}

double Solver::max_penetration() const {
  double d = 0;
  for (const auto& c : p_->pairs) d = std::max(d, c.max_penetration());
  return d;
}

std::array<double, 3> Solver::reaction(const std::string& group) const {
  std::array<double, 3> r{0, 0, 0};
  for (int id : p_->m.group(group))
    for (int d = 0; d < 3; ++d) r[d] += p_->reac[3 * id + d];
  return r;
}

std::array<double, 3> Solver::section_force(const std::string& group) const {
  std::array<double, 3> r{0, 0, 0};
  for (int id : p_->m.group(group))
    for (int d = 0; d < 3; ++d) r[d] += p_->fint[3 * id + d];
  return r;
}

SolverState Solver::state() const {
  const Impl& s = *p_;
  SolverState st;
  st.time = s.time;
  st.dt = s.dt;
  st.dt_contact = s.dt_contact;
  st.step = s.step;
  st.X = s.X;
  st.x = s.x;
  st.v = s.v;
  st.rigid = internal::rigid_velocities(s.con);
  st.e_contact = s.w_contact;
  st.e_damping = s.w_damping;
  st.w_external = s.w_external;
  st.e_initial = s.e_initial;
  st.e_initial_set = s.e_initial_set;
  for (const auto& c : s.pairs) st.contact_history.push_back(c.history());
  return st;
}

void Solver::set_state(const SolverState& st, bool reset_time, bool reset_velocity) {
  Impl& s = *p_;
  if (st.x.size() != 3 * s.n || st.v.size() != 3 * s.n || st.X.size() != 3 * s.n)
    throw pipeline::bad_input(s.m.name, "restart state has " + std::to_string(st.x.size() / 3) +
                                            " nodes, the model has " + std::to_string(s.n));
  for (std::size_t k = 0; k < st.X.size(); ++k)
    if (std::fabs(st.X[k] - s.X[k]) > 1e-9 * (1 + std::fabs(s.X[k])))
      throw pipeline::bad_input(s.m.name, "restart state was written for another mesh (reference node " +
                                              std::to_string(k / 3) + " differs)");
  s.x = st.x;
  s.v = st.v;
  // Tied nodes share one velocity: a later stage may tie nodes the earlier one moved separately.
  if (!s.m.ties.empty()) internal::init_constraint_velocities(s.con, s.x, s.mass, s.v);
  internal::set_rigid_velocities(s.con, st.rigid);
  // Contact history (friction stick forces, sides of two-sided masters, search state): carried
  // over when the state was written with the same contact pairs (a restart, or a later stage with
  // the same deck contacts), so friction keeps its stick forces. A later stage with other pairs
  // starts its contact afresh: its history would not mean anything for them.
  bool same_pairs = st.contact_history.size() == s.pairs.size();
  for (std::size_t k = 0; k < s.pairs.size() && same_pairs; ++k)
    same_pairs = s.pairs[k].history_fits(st.contact_history[k]);
  if (same_pairs)
    for (std::size_t k = 0; k < s.pairs.size(); ++k) s.pairs[k].set_history(st.contact_history[k]);
  if (!reset_time) {
    s.time = st.time;
    s.step = st.step;
    if (st.dt > 0) s.dt = st.dt, s.dt_contact = st.dt_contact > 0 ? st.dt_contact : st.dt;
    s.w_contact = st.e_contact;
    s.w_damping = st.e_damping;
    s.w_external = st.w_external;
    s.e_initial = st.e_initial;
    s.e_initial_set = st.e_initial_set;
    // The saved step is kept (a restarted run is the run it continues), but the stable step
    // reported beside it is the saved state's, not the reference geometry's the constructor
    // measured (sweep Q).
    const auto d = s.compute_stable_dt();
    if (std::isfinite(d.every)) s.dt_stable = std::isfinite(d.free) ? d.free : d.every;
  } else {
    const auto d = s.compute_stable_dt();
    if (s.m.control.dt_target <= 0 && std::isfinite(d.every)) s.choose_step(d.free, d.every);
  }
  if (reset_velocity) {
    // At rest, then the deck's initial velocities, as at t = 0 of a run without a state.
    std::fill(s.v.begin(), s.v.end(), 0.0);
    internal::set_rigid_velocities(s.con, {});
    s.apply_initial_velocities();
    // The kinetic energy changed by fiat, outside the balance: it restarts from the next step
    // (kept, the kinetic energy removed showed as a balance error and could stop the run).
    s.e_initial_set = false;
  }
}

}  // namespace solve
