// Node columns of the layered model: directions, the common depth partition, depth caps and the
// detect-and-fix loop. Written by hand because no library offsets a labelled open surface into
// conforming prism layers with per-part stacks (CGAL/gmsh offer offsets of closed volumes only).
#include "layering/internal/layers_columns.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "layering/internal/layers_geometry.h"
#include "pipeline/error.h"

namespace layering::internal {
namespace {

// Smallest cosine between a column and the inward normal of any incident skin triangle (~50°).
constexpr double kMinColumnCos = 0.65;

Eigen::Vector3d tri_normal(const std::vector<Eigen::Vector3d>& x, const Tri& t) {  // area-weighted (×2)
  return (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
}

// Planar quality of a skin triangle: 2/√3 × min sin(angle); the best a wedge on it can score.
double triangle_quality(const std::vector<Eigen::Vector3d>& x, const Tri& t) {
  double q = 1e9;
  for (int v = 0; v < 3; ++v) {
    const Eigen::Vector3d a = x[t[(v + 1) % 3]] - x[t[v]], b = x[t[(v + 2) % 3]] - x[t[v]];
    q = std::min(q, a.cross(b).norm() / (a.norm() * b.norm() + 1e-300));
  }
  return q * 2.0 / std::sqrt(3.0);
}

std::string centroid(const std::vector<Eigen::Vector3d>& x, const Tri& t) {
  const Eigen::Vector3d c = (x[t[0]] + x[t[1]] + x[t[2]]) / 3;
  return pipeline::format_position_mm(c.x(), c.y(), c.z());
}

// The sharpest fold of the skin at the triangles `at`: the largest angle between the normals of
// two triangles sharing an edge, one of them in `at`, and where (the edge's middle), for the error
// of a fix loop that could not converge: past 2 acos(min scaled Jacobian) (157° at 0.2) no column
// direction at the fold's nodes gives a wedge of either side that quality, and folds a little
// less sharp need more turning than the smoothed directions allow (the real Flex face seal's
// rolled lip: 137-158° on its 2.6 mm surface mesh, 360 wedges bad after 60 passes).
std::string sharpest_fold(const std::vector<Eigen::Vector3d>& x, const std::vector<PartTris>& parts, const std::set<Tri>& at) {
  std::map<std::pair<int, int>, std::vector<const Tri*>> by_edge;
  for (const PartTris& p : parts)
    for (const Tri& t : p.tris)
      for (int v = 0; v < 3; ++v) by_edge[std::minmax(t[v], t[(v + 1) % 3])].push_back(&t);
  double worst_deg = 0;
  Eigen::Vector3d where = Eigen::Vector3d::Zero();
  for (const auto& [edge, tris] : by_edge) {
    if (tris.size() != 2 || (!at.count(*tris[0]) && !at.count(*tris[1]))) continue;
    const double c = tri_normal(x, *tris[0]).normalized().dot(tri_normal(x, *tris[1]).normalized());
    const double deg = std::acos(std::clamp(c, -1.0, 1.0)) * 180 / M_PI;
    if (deg > worst_deg) worst_deg = deg, where = (x[edge.first] + x[edge.second]) / 2;
  }
  return pipeline::format_number(std::round(worst_deg)) + " deg at " + pipeline::format_position_mm(where.x(), where.y(), where.z());
}

}  // namespace

std::vector<std::vector<int>> skin_neighbours(const Input& in) {
  std::vector<std::set<int>> n(in.nodes.size());
  for (const PartTris& p : in.parts)
    for (const Tri& t : p.tris)
      for (int v = 0; v < 3; ++v) {
        n[t[v]].insert(t[(v + 1) % 3]);
        n[t[v]].insert(t[(v + 2) % 3]);
      }
  std::vector<std::vector<int>> out(n.size());
  for (std::size_t i = 0; i < n.size(); ++i) out[i].assign(n[i].begin(), n[i].end());
  return out;
}

std::size_t Columns::reduced_columns() const {
  std::size_t n = 0;
  for (int i : skin) n += scale[i] < 0.999;
  return n;
}
double Columns::min_scale() const {
  double m = 1;
  for (int i : skin) m = std::min(m, scale[i]);
  return m;
}

void limit_depth_gradient(const std::vector<std::vector<int>>& nbr, const std::vector<Eigen::Vector3d>& x,
                          Columns& c) {
  // Iterated to a fixed point (each pass only lowers scales, and every cap is >= the smallest
  // scale, so it terminates); the bound only guards against a bug.
  for (int pass = 0; pass < 10000; ++pass) {
    bool changed = false;
    for (int i : c.skin)
      for (int j : nbr[i]) {
        const double depth = std::min(c.levels[c.max_level[i]], c.levels[c.max_level[j]]);
        if (depth <= 0) continue;
        const double cap = c.scale[j] + kMaxDepthSlope * (x[i] - x[j]).norm() / depth;
        if (c.scale[i] > cap + 1e-12) c.scale[i] = cap, changed = true;
      }
    if (!changed) return;
  }
  throw pipeline::Error(pipeline::ErrorKind::algorithm, "depth taper did not settle in 10000 passes");
}

Columns make_columns(Input& in, const LayerOptions& opt) {
  const auto& x = in.nodes;
  // 1. Orientation of each block: normals point away from the offset side.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::size_t nc = 0;
  for (auto* list : {&in.parts, &in.shells})
    for (const PartTris& p : *list)
      for (const Tri& t : p.tris) centroid += (x[t[0]] + x[t[1]] + x[t[2]]) / 3.0, ++nc;
  centroid /= double(std::max<std::size_t>(nc, 1));
  for (auto* list : {&in.parts, &in.shells})
    for (PartTris& p : *list) {
      double s = 0;
      for (const Tri& t : p.tris) {
        const Eigen::Vector3d n = tri_normal(x, t);
        s += in.respirator ? -n.z() : n.dot((x[t[0]] + x[t[1]] + x[t[2]]) / 3.0 - centroid);
      }
      if (s < 0)
        for (Tri& t : p.tris) std::swap(t[1], t[2]);
    }
  // 2. Skin nodes and area-weighted vertex normals (shells included, so columns on the border
  //    with the back of the head lean like the surface there).
  Columns c;
  const std::size_t n = x.size();
  c.dir.assign(n, Eigen::Vector3d::Zero());
  c.scale.assign(n, 1.0);
  c.max_level.assign(n, 0);
  std::vector<char> is_skin(n, 0);
  for (const PartTris& p : in.parts)
    for (const Tri& t : p.tris)
      for (int v : t) is_skin[v] = 1;
  for (auto* list : {&in.parts, &in.shells})
    for (const PartTris& p : *list)
      for (const Tri& t : p.tris) {
        const Eigen::Vector3d nt = tri_normal(x, t);
        for (int v : t) c.dir[v] -= nt;  // offset direction = minus the outward normal
      }
  for (std::size_t i = 0; i < n; ++i)
    if (is_skin[i]) {
      if (c.dir[i].norm() == 0)
        throw pipeline::bad_input("surface", "the node at " + pipeline::format_position_mm(x[i].x(), x[i].y(), x[i].z()) +
                                                 ": zero normal");
      c.dir[i].normalize();
      c.skin.push_back(int(i));
    }
  // 3. Laplacian smoothing of the directions over the whole face (all parts together), over a
  //    distance rather than a number of rings: each pass diffuses by about one edge, so n passes
  //    reach ~√n edges, and the same count smoothed 4 mm surfaces half as far as 7 mm ones.
  const auto nbr = skin_neighbours(in);
  double edge_sum = 0;
  std::size_t edge_count = 0;
  for (int i : c.skin)
    for (int j : nbr[i]) edge_sum += (x[i] - x[j]).norm(), ++edge_count;
  const double mean_edge_mm = edge_count ? edge_sum / double(edge_count) : 1.0;
  // At most 200 passes (a reach of ~14 edges): beyond that the smoothing would bend the directions
  // of a whole cheek, and the cost grows as the square of the reach (1 mm surfaces at 14 mm: 196).
  c.smoothing_passes = int(std::clamp(std::round(std::pow(opt.smoothing_mm / mean_edge_mm, 2)), 0.0, 200.0));
  const std::vector<Eigen::Vector3d> raw = c.dir;
  for (int it = 0; it < c.smoothing_passes; ++it) {
    std::vector<Eigen::Vector3d> next = c.dir;
    for (int i : c.skin) {
      Eigen::Vector3d m = Eigen::Vector3d::Zero();
      for (int j : nbr[i]) m += c.dir[j];
      if (!nbr[i].empty()) next[i] = (0.5 * c.dir[i] + 0.5 * m / double(nbr[i].size())).normalized();
    }
    c.dir = next;
  }
  // Never lean more than ~60° from the raw vertex normal, nor more than ~50° from the inward normal
  // of any incident skin triangle: the Jacobian at a skin corner of a wedge is set by the triangle
  // and the column DIRECTIONS only, not by the depth, so a leaning column there cannot be fixed by
  // thinning (that is how columns used to be thinned to 0.2 % of their depth in the nose).
  std::vector<std::vector<Eigen::Vector3d>> incident_inward(n);
  for (const PartTris& p : in.parts)
    for (const Tri& t : p.tris) {
      const Eigen::Vector3d nin = -tri_normal(x, t).normalized();
      for (int v : t) incident_inward[v].push_back(nin);
    }
  auto min_cos = [&](int i) {
    double m = 1;
    for (const auto& nt : incident_inward[i]) m = std::min(m, c.dir[i].dot(nt));
    return m;
  };
  for (int i : c.skin) {
    for (int k = 0; k < 10 && c.dir[i].dot(raw[i]) < 0.5; ++k) c.dir[i] = (c.dir[i] + raw[i]).normalized();
    for (int k = 0; k < 20 && min_cos(i) < kMinColumnCos; ++k) c.dir[i] = (c.dir[i] + 0.25 * raw[i]).normalized();
  }
  // 4. The common depth partition: union of all interfaces and sub-layer levels.
  std::set<double> lv{0.0};
  for (const PartTris& p : in.parts) {
    double cum = 0;
    for (const auto& [mat, th] : p.stack) {
      auto it = opt.elements_per_tissue.find(mat);
      const int ne = it != opt.elements_per_tissue.end() ? it->second : opt.elements_per_layer;
      for (int m = 1; m <= ne; ++m) lv.insert(std::round((cum + th * m / ne) * 1e6) / 1e6);
      cum += th;
    }
  }
  c.levels.assign(lv.begin(), lv.end());
  for (const PartTris& p : in.parts) {
    double cum = 0;
    std::vector<double> ends;
    for (const auto& l : p.stack) ends.push_back(cum += l.second);
    std::vector<int>& tol = c.tissue_of_level[p.name];
    for (std::size_t k = 0; k + 1 < c.levels.size() && c.levels[k + 1] <= cum + 1e-9; ++k) {
      std::size_t j = 0;
      while (j + 1 < ends.size() && c.levels[k] >= ends[j] - 1e-9) ++j;
      tol.push_back(int(j));
    }
    for (const Tri& t : p.tris)
      for (int v : t) c.max_level[v] = std::max(c.max_level[v], int(tol.size()));
  }
  // 5. Depth caps from ray casts: a column may use at most ray_fraction of the distance to the
  //    surface it points at (nose, chin: two offsets from opposite sides must not meet).
  std::vector<Tri> all;
  for (auto* list : {&in.parts, &in.shells})
    for (const PartTris& p : *list) all.insert(all.end(), p.tris.begin(), p.tris.end());
  std::vector<Eigen::Vector3d> dirs;
  for (int i : c.skin) dirs.push_back(c.dir[i]);
  const std::vector<double> hit = ray_hit_distances(x, all, c.skin, dirs);
  for (std::size_t q = 0; q < c.skin.size(); ++q) {
    const int i = c.skin[q];
    const double depth = c.levels[c.max_level[i]];
    if (std::isfinite(hit[q]) && depth > 0) c.scale[i] = std::min(1.0, opt.ray_fraction * hit[q] / depth);
  }
  // 6. Depth caps where columns converge (convex places: the nose, the chin's rim): two neighbouring
  //    columns i, j whose lines approach each other would cross at some depth; cap both where the
  //    edge between them has shrunk to kConvergedEdgeFraction of its skin length, before they
  //    cross. Closed form (|Δp + t·Δd|² = f²|Δp|², smallest root) instead of blind thinning. Only a
  //    first guess: the detect-and-fix loop below measures the wedges and thins further where
  //    needed. 0.35 rather than 0.5: at 0.5 one converging edge pair at the nose's lower edge was
  //    cut to 0.43-0.51 of its depth on the generated small/shortwide heads, and the taper around it
  //    cost that cheek up to 4.8 % of its volume (issue 4: 5 %); at 0.35 the worst part x layer of
  //    the six chain heads at 6.4 and 7 mm is -4.4 % (a forehead; cheeks -3.4 % at worst) for
  //    1-3 extra fix passes, min scaled Jacobian still >= 0.2 (layering/README.md).
  constexpr double kConvergedEdgeFraction = 0.35;
  for (int i : c.skin) {
    const double depth_i = c.levels[c.max_level[i]];
    if (depth_i <= 0) continue;
    for (int j : nbr[i]) {
      const Eigen::Vector3d dp = x[j] - x[i], dd = c.dir[j] - c.dir[i];
      const double a = dd.squaredNorm(), b = 2 * dp.dot(dd),
                   cc = (1 - kConvergedEdgeFraction * kConvergedEdgeFraction) * dp.squaredNorm();
      const double disc = b * b - 4 * a * cc;
      if (b >= 0 || a <= 0 || disc < 0) continue;  // diverging or never shrinking that far
      const double t_cap = (-b - std::sqrt(disc)) / (2 * a);
      c.scale[i] = std::min(c.scale[i], t_cap / depth_i);
    }
  }
  limit_depth_gradient(nbr, x, c);
  return c;
}

std::size_t fix_columns(const Input& in, const LayerOptions& opt, Columns& c, pipeline::Progress* progress) {
  const auto& x = in.nodes;
  for (const PartTris& p : in.parts)
    for (std::size_t e = 0; e < p.tris.size(); ++e) {
      const double q = triangle_quality(x, p.tris[e]);
      if (q < opt.min_scaled_jacobian)
        throw pipeline::bad_input("surface", "part " + p.name + "'s triangle " + std::to_string(e + 1) + " of " +
                                                 std::to_string(p.tris.size()) + ", at " + centroid(x, p.tris[e]) +
                                                 ", too distorted for wedges: shape quality " + pipeline::format_number(q) +
                                                 ", expected >= " + pipeline::format_number(opt.min_scaled_jacobian) +
                                                 " (remesh the surface)");
    }
  const auto nbr = skin_neighbours(in);
  // the surface the wedges grow from, for the messages: a respirator has no skin (sweep K)
  const std::string surface = opt.kind == "respirator" ? "inner face" : "skin";
  std::string last;  // the last pass's bad wedges: how many, what and where, for the error
  std::set<Tri> last_bad;  // and their skin triangles
  for (int iter = 0; iter < opt.max_fix_iterations; ++iter) {
    // Build the current wedges (all parts) and shells as one model.
    FeModel m;
    m.nodes = x;
    std::vector<std::vector<int>> id(x.size());
    for (int i : c.skin) {
      id[i].assign(c.max_level[i] + 1, i);
      for (int k = 1; k <= c.max_level[i]; ++k) {
        id[i][k] = int(m.nodes.size());
        m.nodes.push_back(c.position(x, i, k));
      }
    }
    Block w{"wedges", 3, 6, {}}, sh{"shells", 2, 3, {}};
    std::vector<std::pair<Tri, Eigen::Vector3d>> owner;  // columns and inward normal of each wedge
    std::set<int> bad;
    for (const PartTris& p : in.parts) {
      const int nlev = int(c.tissue_of_level.at(p.name).size());
      for (const Tri& t : p.tris) {
        const Eigen::Vector3d nin = -tri_normal(x, t).normalized();
        for (int k = 0; k < nlev; ++k) {
          Eigen::Vector3d pts[6];
          int ids[6];
          for (int v = 0; v < 3; ++v) {
            ids[v] = id[t[v]][k + 1];
            ids[v + 3] = id[t[v]][k];
            pts[v] = m.nodes[ids[v]];
            pts[v + 3] = m.nodes[ids[v + 3]];
          }
          if (wedge_scaled_jacobian(pts) < opt.min_scaled_jacobian || wedge_volume(pts) <= 0)
            bad.insert(int(owner.size()));
          w.conn.insert(w.conn.end(), ids, ids + 6);
          owner.push_back({t, nin});
        }
      }
    }
    std::string what = "wedges below quality";
    if (bad.empty()) {
      for (const PartTris& s : in.shells)
        for (const Tri& t : s.tris) sh.conn.insert(sh.conn.end(), {t[0], t[1], t[2]});
      m.blocks = {w, sh};
      std::vector<Tri> tris;
      std::vector<std::pair<int, int>> own;
      element_faces(m, &tris, &own);
      const auto pairs = intersecting_triangles(m.nodes, tris);
      for (auto [a, b] : pairs)
        for (int f : {a, b})
          if (own[f].first == 0) bad.insert(own[f].second);
      what = "wedges with intersecting faces";
      if (bad.empty()) return pairs.size();  // pairs of shell triangles: no column moves them
    }
    if (progress) progress->step("fix pass " + std::to_string(iter + 1) + ": " + std::to_string(bad.size()) + " " + what);
    last = std::to_string(bad.size()) + " " + what + ", the first on the " + surface + " at " + centroid(x, owner[*bad.begin()].first);
    // Two causes, two fixes. If the wedge's skin triangle with its column directions (depth-free:
    // a 0.1 mm prism) is already below the threshold, the columns lean too far: turn them toward
    // the triangle's normal and keep the depth. Otherwise the deep part is squeezed: thin locally.
    // Each bad skin triangle acts once per pass, however many of its stacked wedges are bad: acting
    // once per wedge turned a column up to 7 times in one pass, overshooting so that the neighbours
    // across a sharp tip went bad in turn (NIOSH medium chain surface, nose tip: 21 <-> 28 bad
    // wedges for 60 passes).
    std::set<int> cols;
    std::set<Tri> done;
    for (int e : bad) {
      const Tri& t = owner[e].first;
      if (!done.insert(t).second) continue;
      Eigen::Vector3d prism[6];
      for (int v = 0; v < 3; ++v) {
        prism[v] = x[t[v]] + 0.1 * c.dir[t[v]];
        prism[v + 3] = x[t[v]];
      }
      const bool leaning = wedge_scaled_jacobian(prism) < opt.min_scaled_jacobian + 0.02;
      for (int v : t) {
        if (leaning) {
          c.dir[v] = (c.dir[v] + 0.5 * owner[e].second).normalized();
        } else {
          if (cols.insert(v).second) c.scale[v] *= 0.85;
          c.dir[v] = (c.dir[v] + 0.2 * owner[e].second).normalized();
        }
      }
    }
    last_bad = std::move(done);
    limit_depth_gradient(nbr, x, c);
  }
  throw pipeline::Error(pipeline::ErrorKind::algorithm,
                        "wedges still inverted, distorted or intersecting after " + std::to_string(opt.max_fix_iterations) +
                            " thinning passes: " + last + "; the " + surface + "'s sharpest fold there is " +
                            sharpest_fold(x, in.parts, last_bad) + " (a fold or a gap narrower than the layers?)");
}

void element_faces(const FeModel& m, std::vector<Tri>* tris, std::vector<std::pair<int, int>>* owner) {
  std::map<std::array<int, 3>, int> seen;
  auto add = [&](Tri t, int b, int e) {
    Tri key = t;
    std::sort(key.begin(), key.end());
    if (seen.emplace(key, int(tris->size())).second) {
      tris->push_back(t);
      owner->push_back({b, e});
    }
  };
  auto add_quad = [&](int a, int b, int cc, int d, int bl, int e) {
    if (std::min(a, cc) < std::min(b, d)) add({a, b, cc}, bl, e), add({a, cc, d}, bl, e);
    else add({a, b, d}, bl, e), add({b, cc, d}, bl, e);
  };
  for (std::size_t bi = 0; bi < m.blocks.size(); ++bi) {
    const Block& b = m.blocks[bi];
    for (std::size_t e = 0; e < b.size(); ++e) {
      const int* v = &b.conn[e * b.nodes_per_elem];
      if (b.dim == 3 && b.nodes_per_elem == 6) {
        add({v[0], v[1], v[2]}, int(bi), int(e));
        add({v[3], v[4], v[5]}, int(bi), int(e));
        add_quad(v[0], v[1], v[4], v[3], int(bi), int(e));
        add_quad(v[1], v[2], v[5], v[4], int(bi), int(e));
        add_quad(v[2], v[0], v[3], v[5], int(bi), int(e));
      } else if (b.dim == 2 && b.nodes_per_elem == 3) {
        add({v[0], v[1], v[2]}, int(bi), int(e));
      } else if (b.dim == 2 && b.nodes_per_elem == 4) {
        add_quad(v[0], v[1], v[2], v[3], int(bi), int(e));
      }
    }
  }
}

}  // namespace layering::internal
