// build_layers: offset the face parts into conforming wedge layers (see layers.h for the method).
#include "layering/layers.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "layering/internal/layers_columns.h"
#include "layering/internal/layers_geometry.h"
#include "pipeline/error.h"
#include "pipeline/progress.h"

namespace layering {
namespace {

using internal::Columns;
using internal::Tri;

std::string group_name(const std::string& part, const std::string& material) {
  std::string m = material;
  const std::string suffix = "_layer";
  if (m.size() > suffix.size() && m.compare(m.size() - suffix.size(), suffix.size(), suffix) == 0)
    m.resize(m.size() - suffix.size());
  const std::string p = part == "respirator_inner" ? "respirator" : part;
  return p + "_" + m;
}

}  // namespace

FeModel build_layers(const FeModel& surface, const std::map<std::string, Stack>& stacks, const LayerOptions& opt,
                     LayerReport* report) {
  pipeline::Progress progress("layers", 0);
  // 1. Sort the triangle blocks into layered parts and rigid shells.
  internal::Input in;
  in.nodes = surface.nodes;
  in.respirator = opt.kind == "respirator";
  for (const Block& b : surface.blocks) {
    if (b.dim != 2) continue;
    if (b.nodes_per_elem != 3)
      throw pipeline::bad_input("block " + b.name, "expected 3-node triangles, got " + std::to_string(b.nodes_per_elem) + "-node elements");
    auto it = stacks.find(b.name);
    internal::PartTris pt{b.name, {}, it == stacks.end() ? Stack{} : it->second};
    for (std::size_t e = 0; e < b.size(); ++e) pt.tris.push_back({b.conn[3 * e], b.conn[3 * e + 1], b.conn[3 * e + 2]});
    (it == stacks.end() ? in.shells : in.parts).push_back(std::move(pt));
  }
  if (in.parts.empty()) {
    std::string names;
    for (auto& [k, v] : stacks) names += (names.empty() ? "" : ", ") + k;
    throw pipeline::bad_input("surface", "no triangle group named after a layered part (" + names + ")");
  }
  // A named group without elements (a file whose element section was lost) would be layered
  // into nothing and written as an empty model.
  for (const internal::PartTris& p : in.parts)
    if (p.tris.empty()) throw pipeline::bad_input("surface", "part " + p.name + " has no triangles");
  // 2. Orientation, offset directions, the common depth partition.
  Columns c = internal::make_columns(in, opt);
  progress.step("directions (" + std::to_string(c.smoothing_passes) + " smoothing passes) and depth caps for " +
                std::to_string(c.skin.size()) + " skin nodes");
  // 3. Detect and fix: quality of every wedge, then intersections of all element faces.
  const std::size_t shell_pairs = internal::fix_columns(in, opt, c, &progress);
  if (shell_pairs)
    throw pipeline::Error(pipeline::ErrorKind::algorithm,
                          "shell triangles (of the groups without layers) intersect in " + std::to_string(shell_pairs) +
                              " pairs: a self-intersecting surface (repair it)");
  // 4. Assemble the output model.
  FeModel out;
  out.nodes = surface.nodes;
  std::vector<std::vector<int>> node_at(surface.nodes.size());
  for (int i : c.skin) {
    node_at[i].assign(c.max_level[i] + 1, i);
    for (int k = 1; k <= c.max_level[i]; ++k) {
      node_at[i][k] = int(out.nodes.size());
      out.nodes.push_back(c.position(in.nodes, i, k));
    }
  }
  LayerReport r;
  r.min_scaled_jacobian = 1e9;
  r.min_volume = 1e300;
  Block all_skin{in.respirator ? "respirator_inner" : "head_skin", 2, 3, {}};
  for (const internal::PartTris& p : in.parts) {
    const std::vector<int>& tissue_of_level = c.tissue_of_level.at(p.name);
    const int nlev = int(tissue_of_level.size());
    std::vector<Block> tissue(p.stack.size());
    std::vector<LayerVolume> vols(p.stack.size());
    auto full_depth = [&](const Tri& t) { return c.scale[t[0]] >= 0.999 && c.scale[t[1]] >= 0.999 && c.scale[t[2]] >= 0.999; };
    double cum = 0;
    for (std::size_t j = 0; j < p.stack.size(); ++j) {
      tissue[j] = Block{group_name(p.name, p.stack[j].first), 3, 6, {}};
      vols[j].group = tissue[j].name;
      vols[j].thickness = p.stack[j].second;
      const double dmid = cum + 0.5 * p.stack[j].second;
      cum += p.stack[j].second;
      for (const Tri& t : p.tris) {
        Eigen::Vector3d q[3], s[3];
        for (int v = 0; v < 3; ++v) {
          q[v] = in.nodes[t[v]] + dmid * c.dir[t[v]];
          s[v] = in.nodes[t[v]];
        }
        const double mid = 0.5 * (q[1] - q[0]).cross(q[2] - q[0]).norm() * p.stack[j].second;
        const double skin_a = 0.5 * (s[1] - s[0]).cross(s[2] - s[0]).norm() * p.stack[j].second;
        vols[j].mid_area_volume += mid;
        vols[j].skin_area_volume += skin_a;
        if (full_depth(t)) vols[j].full_depth_mid_area_volume += mid, vols[j].full_depth_area_fraction += skin_a;
      }
      vols[j].full_depth_area_fraction /= std::max(vols[j].skin_area_volume, 1e-300);
    }
    Block skin{p.name + "_skin_surface", 2, 3, {}}, bone{p.name + "_bone_inner", 2, 3, {}};
    for (const Tri& t : p.tris) {
      for (int k = 0; k < nlev; ++k) {
        Eigen::Vector3d w[6];
        int ids[6];
        for (int v = 0; v < 3; ++v) {
          ids[v] = node_at[t[v]][k + 1];
          ids[v + 3] = node_at[t[v]][k];
          w[v] = out.nodes[ids[v]];
          w[v + 3] = out.nodes[ids[v + 3]];
        }
        const int j = tissue_of_level[k];
        tissue[j].conn.insert(tissue[j].conn.end(), ids, ids + 6);
        const double vol = wedge_volume(w);
        vols[j].volume += vol;
        if (full_depth(t)) vols[j].full_depth_volume += vol;
        vols[j].wedges++;
        r.min_volume = std::min(r.min_volume, vol);
        r.min_scaled_jacobian = std::min(r.min_scaled_jacobian, wedge_scaled_jacobian(w));
        r.wedges++;
      }
      skin.conn.insert(skin.conn.end(), {t[0], t[1], t[2]});
      // Bone inner surface: the deepest level, normal pointing deeper (out of the tissue).
      bone.conn.insert(bone.conn.end(), {node_at[t[0]][nlev], node_at[t[2]][nlev], node_at[t[1]][nlev]});
    }
    all_skin.conn.insert(all_skin.conn.end(), skin.conn.begin(), skin.conn.end());
    for (std::size_t j = 0; j < tissue.size(); ++j) {
      out.blocks.push_back(std::move(tissue[j]));
      r.volumes.push_back(vols[j]);
    }
    if (!in.respirator) {
      out.blocks.push_back(std::move(skin));
      out.blocks.push_back(std::move(bone));
    }
  }
  for (const internal::PartTris& s : in.shells) {
    Block b{s.name, 2, 3, {}};
    for (const Tri& t : s.tris) b.conn.insert(b.conn.end(), {t[0], t[1], t[2]});
    all_skin.conn.insert(all_skin.conn.end(), b.conn.begin(), b.conn.end());
    r.shell_triangles += s.tris.size();
    out.blocks.push_back(std::move(b));
  }
  out.blocks.push_back(std::move(all_skin));
  if (in.respirator) {
    // The rim: boundary edges of the inner face (attachment points of the straps sit on it).
    std::map<std::pair<int, int>, int> edges;
    for (const Tri& t : in.parts[0].tris)
      for (int v = 0; v < 3; ++v) edges[{std::min(t[v], t[(v + 1) % 3]), std::max(t[v], t[(v + 1) % 3])}]++;
    Block rim{"respirator_rim", 1, 2, {}};
    for (auto& [e, n] : edges)
      if (n == 1) rim.conn.insert(rim.conn.end(), {e.first, e.second});
    out.blocks.push_back(std::move(rim));
  }
  r.nodes = out.nodes.size();
  r.reduced_columns = c.reduced_columns();
  r.min_depth_scale = c.min_scale();
  // fix_columns' last pass found no two element faces intersecting, on these very faces: out's
  // nodes are the same c.position of the same columns, its wedges the same, its shells too, and
  // its skin and bone-inner groups faces of the wedges. Counting again here took ~45 % of the
  // stage (0.8 of 1.7 s on medium_onesize); the tests count on the written model instead.
  r.intersecting_pairs = shell_pairs;
  std::ostringstream msg;
  msg << r.wedges << " wedges, min scaled Jacobian " << r.min_scaled_jacobian << ", " << r.reduced_columns
      << " columns thinned (min depth scale " << r.min_depth_scale << ")";
  // step, not finish: the program has yet to write the model, and a failed write must not follow a "done"
  progress.step("layered: " + msg.str());
  if (report) *report = r;
  return out;
}

std::vector<std::string> volume_shortfall_warnings(const LayerReport& report, double max_shortfall) {
  std::vector<std::pair<double, std::string>> short_groups;
  for (const auto& v : report.volumes)
    if (const double shortfall = 1 - v.volume / v.mid_area_volume; shortfall > max_shortfall)
      short_groups.emplace_back(shortfall, v.group);
  std::sort(short_groups.rbegin(), short_groups.rend());
  std::vector<std::string> lines;
  for (const auto& [shortfall, group] : short_groups) {
    char line[240];
    std::snprintf(line, sizeof line,
                  "%s holds %.1f %% less than its mid-area x thickness (%zu columns of the model thinned where the stack does not fit)",
                  group.c_str(), 100 * shortfall, report.reduced_columns);
    lines.push_back(line);
  }
  return lines;
}

}  // namespace layering
