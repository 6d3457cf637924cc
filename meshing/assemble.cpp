// Placement of the respirator, the merged solver model and the solver decks.
#include "meshing/assemble.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <set>

#include "layering/internal/layers_columns.h"
#include "layering/internal/layers_geometry.h"
#include "meshing/internal/assemble_geometry.h"
#include "pipeline/error.h"
#include "pipeline/read_landmarks.h"

namespace meshing {
namespace {

using layering::Block;
using layering::FeModel;
using Tris = std::vector<std::array<int, 3>>;

// All respirator element faces as triangles (wedges: their 8 triangles; shells as they are).
Tris body_triangles(const FeModel& m) {
  Tris t;
  for (const Block& b : m.blocks) {
    for (std::size_t e = 0; e < b.size(); ++e) {
      const int* v = &b.conn[e * b.nodes_per_elem];
      if (b.nodes_per_elem == 3 && b.dim == 2) t.push_back({v[0], v[1], v[2]});
      if (b.nodes_per_elem == 4 && b.dim == 2) t.push_back({v[0], v[1], v[2]}), t.push_back({v[0], v[2], v[3]});
      if (b.nodes_per_elem == 6) {
        t.push_back({v[0], v[1], v[2]});
        t.push_back({v[3], v[4], v[5]});
        for (auto [a, c, d, f] : {std::array<int, 4>{0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}})
          t.push_back({v[a], v[c], v[d]}), t.push_back({v[a], v[d], v[f]});
      }
    }
  }
  return t;
}

// The gap between the head's skin and the respirator shifted by s: the smallest of the respirator
// nodes' signed distances to the skin and the skin nodes' distances to the respirator's element
// faces. Both trees are built once; a shift moves the queries instead (q - s against the respirator
// at rest), so the bisection of place_respirator does not rebuild the respirator's tree per step.
class Gap {
 public:
  Gap(const FeModel& head, const FeModel& resp)
      : head_tree_(head.nodes, head_surface(head)), resp_(resp), resp_tree_(resp.nodes, body_triangles(resp)) {
    std::vector<int> skin;  // the skin's nodes, each once
    for (const auto& t : head_surface(head)) skin.insert(skin.end(), t.begin(), t.end());
    std::sort(skin.begin(), skin.end());
    skin.erase(std::unique(skin.begin(), skin.end()), skin.end());
    for (int v : skin) skin_points_.push_back(head.nodes[v]);
    lo_ = hi_ = resp.nodes[0];
    for (const auto& p : resp.nodes) lo_ = lo_.cwiseMin(p), hi_ = hi_.cwiseMax(p);
    known_.assign(skin_points_.size(), {-1e300, Eigen::Vector3d::Zero()});
  }

  /// The head's skin, as an AABB tree (for other distances to it, rim_on_face).
  const internal::TriangleTree& skin() const { return head_tree_; }

  /// The gap [mm] at shift s.
  double at(const Eigen::Vector3d& s) const {
    double g = 1e300;
    for (const auto& p : resp_.nodes) g = std::min(g, head_tree_.signed_distance(p + s));
    // A skin node farther from the respirator's box than the smallest gap so far cannot lower it.
    for (const auto& q : skin_points_)
      if (box_distance(q - s) < g) g = std::min(g, resp_tree_.distance(q - s));
    return g;
  }

  /// Whether at(s) > gap_mm, with as few distance queries as it can: it stops at the first distance
  /// within gap_mm, and skips a skin node whose distance is known to exceed gap_mm from its box
  /// distance or from its distance at an earlier shift (a distance changes by at most the shift's
  /// change). The bounds must clear gap_mm by 1e-9 mm, far above rounding, so the answer is at's.
  bool exceeds(const Eigen::Vector3d& s, double gap_mm) {
    for (const auto& p : resp_.nodes)
      if (head_tree_.signed_distance(p + s) <= gap_mm) return false;
    const double clear = gap_mm + 1e-9;
    for (std::size_t i = 0; i < skin_points_.size(); ++i) {
      const Eigen::Vector3d q = skin_points_[i] - s;
      if (box_distance(q) > clear || known_[i].first - (s - known_[i].second).norm() > clear) continue;
      const double d = resp_tree_.distance(q);
      known_[i] = {d, s};
      if (d <= gap_mm) return false;
    }
    return true;
  }

 private:
  double box_distance(const Eigen::Vector3d& q) const { return (q - q.cwiseMax(lo_).cwiseMin(hi_)).norm(); }

  internal::TriangleTree head_tree_;
  const FeModel& resp_;
  internal::TriangleTree resp_tree_;
  std::vector<Eigen::Vector3d> skin_points_;
  Eigen::Vector3d lo_, hi_;  ///< the respirator's box at rest
  std::vector<std::pair<double, Eigen::Vector3d>> known_;  ///< per skin node: a distance and its shift
};

}  // namespace

std::map<std::string, Eigen::Vector3d> read_landmarks(const std::string& path) {
  std::map<std::string, Eigen::Vector3d> positions;
  for (const auto& [name, l] : pipeline::read_landmarks(path, {"sellion", "menton"})) positions[name] = l.position;
  return positions;
}

Tris head_surface(const FeModel& head) {
  Tris t;
  const Block* skin = head.find("head_skin");
  for (const Block& b : head.blocks)
    if (b.dim == 2 && b.nodes_per_elem == 3 && (skin ? &b == skin : true))
      for (std::size_t e = 0; e < b.size(); ++e) t.push_back({b.conn[3 * e], b.conn[3 * e + 1], b.conn[3 * e + 2]});
  if (t.empty()) throw pipeline::bad_input("head", "no triangle group for the skin surface");
  return t;
}

void require_layered(const FeModel& model, const std::string& path, const std::string& kind) {
  bool wedges = false;
  for (const Block& b : model.blocks) wedges = wedges || (b.dim == 3 && b.nodes_per_elem == 6);
  const std::string not_layers = ": not a " + kind + " from layers (a surface.msh, or the other body's layers.msh?)";
  if (!wedges) throw pipeline::bad_input(path, "no wedge layers" + not_layers);
  for (const char* g : kind == "head" ? std::vector<const char*>{"head_skin"}
                                      : std::vector<const char*>{"respirator_inner", "respirator_rim"})
    if (!model.find(g)) throw pipeline::bad_input(path, std::string("no group ") + g + not_layers);
  if (model.find(kind == "head" ? "respirator_inner" : "head_skin") || model.find("strap_top"))
    throw pipeline::bad_input(path, "holds " + std::string(kind == "head" ? "a respirator" : "a head") +
                                        " or straps: an assembled model, not a " + kind + " from layers");
  // A head whose wedges were turned inside out (top and bottom swapped) gave straps 47 mm off
  // and a placement failure far from the cause.
  for (const Block& b : model.blocks) {
    if (b.dim != 3 || b.nodes_per_elem != 6) continue;
    for (std::size_t e = 0; e < b.size(); ++e) {
      Eigen::Vector3d p[6];
      for (int k = 0; k < 6; ++k) p[k] = model.nodes[b.conn[6 * e + k]];
      if (!(layering::wedge_scaled_jacobian(p) > 0))
        throw pipeline::bad_input(path, "wedge " + std::to_string(e) + " of " + b.name +
                                            " is inverted or flat: not a " + kind + " as layers writes it");
    }
  }
}

void require_straps(const FeModel& straps, const std::string& path) {
  const std::string not_straps = ": not straps' output (a model, or a surface or layers .msh?)";
  if (straps.find("head_skin") || straps.find("respirator_inner"))
    throw pipeline::bad_input(path, "holds a head or a respirator" + not_straps);
  for (const char* s : {"top", "bottom"}) {
    const std::string strap = std::string("strap_") + s;
    const Block* quads = straps.find(strap);
    if (!quads || quads->dim != 2 || quads->nodes_per_elem != 4 || quads->size() == 0)
      throw pipeline::bad_input(path, "no group " + strap + " of quads" + not_straps);
    for (const char* side : {"left", "right"}) {
      const Block* attach = straps.find(strap + "_attach_" + side);
      if (!attach || attach->dim != 0 || attach->size() != 1)
        throw pipeline::bad_input(path, "no attachment point " + strap + "_attach_" + side + not_straps);
      const Block* end = straps.find(strap + "_end_" + side);
      if (!end || end->dim != 1 || end->size() == 0)
        throw pipeline::bad_input(path, "no end line " + strap + "_end_" + side + not_straps);
    }
  }
}

void require_landmarks_near_skin(const FeModel& head, const std::map<std::string, Eigen::Vector3d>& lm,
                                 const std::string& path, double max_mm) {
  const internal::TriangleTree skin(head.nodes, head_surface(head));
  for (const auto& [name, p] : lm)
    if (const double d = skin.distance(p); !(d <= max_mm))
      throw pipeline::bad_input(path, "landmark " + name + " at (" + pipeline::format_number(p.x()) + ", " +
                                          pipeline::format_number(p.y()) + ", " + pipeline::format_number(p.z()) +
                                          ") is " + pipeline::format_number(d) + " mm from the head's skin, expected <= " +
                                          pipeline::format_number(max_mm) +
                                          " mm (landmarks of another head, or not in align's frame?)");
}

std::vector<int> rim_nodes(const FeModel& resp) {
  const Block* rim = resp.find("respirator_rim");
  std::vector<int> out = rim ? rim->conn : std::vector<int>{};
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  if (out.empty()) throw pipeline::bad_input("respirator", "no respirator_rim group (run layers --kind respirator first)");
  return out;
}

double respirator_gap(const FeModel& head, const FeModel& resp) { return Gap(head, resp).at(Eigen::Vector3d::Zero()); }

namespace {

// rim_to_skin against a skin tree built already (place_respirator's Gap holds one).
RimOnFace rim_on_face(const internal::TriangleTree& skin, const FeModel& resp, const Eigen::Vector3d& shift) {
  std::vector<double> d;
  for (int i : rim_nodes(resp)) d.push_back(skin.distance(resp.nodes[std::size_t(i)] + shift));
  RimOnFace r;
  r.nodes = d.size();
  std::sort(d.begin(), d.end());
  r.median_mm = d[d.size() / 2];
  r.max_mm = d.back();
  return r;
}

}  // namespace

RimOnFace rim_to_skin(const FeModel& head, const FeModel& resp, const Eigen::Vector3d& shift) {
  return rim_on_face(internal::TriangleTree(head.nodes, head_surface(head)), resp, shift);
}

void require_rim_on_face(const RimOnFace& rim, double max_median_mm) {
  if (rim.median_mm <= max_median_mm) return;
  throw pipeline::bad_input("respirator", "placed on the face, its rim stands " + pipeline::format_number(std::round(rim.median_mm * 10) / 10) +
                                              " mm off the skin (median of its " + std::to_string(rim.nodes) + " nodes; largest " +
                                              pipeline::format_number(std::round(rim.max_mm * 10) / 10) + " mm), more than " +
                                              pipeline::format_number(max_median_mm) +
                                              " mm: a respirator that does not meet the face (is the scan a whole cup, "
                                              "aligned with its open side toward the face, and of a size for this head? "
                                              "--max-rim-off-mm raises the limit)");
}

Eigen::Vector3d place_respirator(const FeModel& head, const std::map<std::string, Eigen::Vector3d>& lm,
                                 const FeModel& resp, const PlaceOptions& opt, double* gap_out, RimOnFace* rim_out) {
  const std::vector<int> rim = rim_nodes(resp);
  double xmin = 1e300, xmax = -1e300, ytop = -1e300;
  for (int i : rim) {
    xmin = std::min(xmin, resp.nodes[i].x());
    xmax = std::max(xmax, resp.nodes[i].x());
    ytop = std::max(ytop, resp.nodes[i].y());
  }
  Eigen::Vector3d s;
  s.x() = 0.5 * (lm.at("sellion").x() + lm.at("menton").x()) - 0.5 * (xmin + xmax);
  s.y() = lm.at("sellion").y() - opt.bridge_offset_mm - ytop;
  double head_zmax = -1e300, resp_zmin = 1e300;
  for (const auto& p : head.nodes) head_zmax = std::max(head_zmax, p.z());
  for (const auto& p : resp.nodes) resp_zmin = std::min(resp_zmin, p.z());
  Gap gap(head, resp);
  // Far in front (gap > target), then step back until closer than the target, then bisect.
  double far = head_zmax + opt.gap_mm + 5 - resp_zmin, near = far;
  auto keeps_gap = [&](double z) { return gap.exceeds(Eigen::Vector3d(s.x(), s.y(), z), opt.gap_mm); };
  for (int k = 0; k < 100 && keeps_gap(near); ++k) far = near, near -= 4.0;
  if (keeps_gap(near))
    throw pipeline::algorithm_failed("placement", "the respirator never comes within the gap of the face");
  for (int k = 0; k < 40 && far - near > 1e-3; ++k) {
    const double mid = 0.5 * (far + near);
    (keeps_gap(mid) ? far : near) = mid;
  }
  s.z() = far;  // the side that keeps at least the gap
  if (gap_out) *gap_out = gap.at(s);
  const RimOnFace rim_fit = rim_on_face(gap.skin(), resp, s);
  if (rim_out) *rim_out = rim_fit;
  require_rim_on_face(rim_fit, opt.max_rim_off_mm);
  return s;
}

FeModel assemble_model(const FeModel& head, const FeModel& resp, const FeModel& straps,
                       const std::map<std::string, Eigen::Vector3d>& lm, const PlaceOptions& opt,
                       AssembleReport* report) {
  AssembleReport r;
  RimOnFace rim_fit;
  r.shift = place_respirator(head, lm, resp, opt, &r.gap_mm, &rim_fit);
  r.rim_median_mm = rim_fit.median_mm;
  r.rim_max_mm = rim_fit.max_mm;
  FeModel out = head;
  // Appends m's nodes that its kept blocks use, and those blocks renumbered. The straps'
  // attachment markers (points of their own) are replaced by rim nodes below, and their nodes
  // are left out: kept, they were 4 nodes of no element, which gmsh drops when it converts the
  // model to msh 2.2, and the deck's model_check then refused the converted copy.
  auto append = [&](const FeModel& m, const Eigen::Vector3d& shift, bool skip_attach) {
    const int base = int(out.nodes.size());
    std::vector<int> index(m.nodes.size(), -1);
    for (const Block& b : m.blocks)
      if (!(skip_attach && b.dim == 0))
        for (int v : b.conn) index[std::size_t(v)] = 0;
    for (std::size_t i = 0; i < m.nodes.size(); ++i)
      if (index[i] == 0 || !skip_attach) {
        index[i] = int(out.nodes.size());
        out.nodes.push_back(m.nodes[i] + shift);
      }
    for (Block b : m.blocks) {
      if (skip_attach && b.dim == 0) continue;  // straps' attachment markers: replaced below
      for (int& v : b.conn) v = index[std::size_t(v)];
      out.blocks.push_back(std::move(b));
    }
    return base;
  };
  const int rbase = append(resp, r.shift, false);
  append(straps, Eigen::Vector3d::Zero(), true);
  // Attachment points: the rim node nearest to each strap attachment marker.
  const std::vector<int> rim = rim_nodes(resp);
  for (const Block& b : straps.blocks) {
    if (b.dim != 0 || b.size() != 1) continue;
    const Eigen::Vector3d a = straps.nodes[b.conn[0]];
    int best = rim[0];
    for (int i : rim)
      if ((resp.nodes[i] + r.shift - a).norm() < (resp.nodes[best] + r.shift - a).norm()) best = i;
    // straps places the respirator as assemble does and puts each marker on a rim node (0.00 mm
    // off when both ran with the same options); a straps file made for another gap, bridge offset
    // or respirator routed its bands to points the respirator is not at. The respirator's place
    // follows the head and the landmarks too: another case's landmarks or head failed here, and
    // the message had named only the straps' options and the respirator.
    const double offset_mm = (resp.nodes[best] + r.shift - a).norm();
    r.attach_offset_mm = std::max(r.attach_offset_mm, offset_mm);
    constexpr double max_attach_offset_mm = 0.5;
    if (offset_mm > max_attach_offset_mm)
      throw pipeline::bad_input("--straps", b.name + " lies " + pipeline::format_number(offset_mm) +
                                                " mm from the respirator's rim as placed here (gap " +
                                                pipeline::format_number(opt.gap_mm) + " mm, bridge offset " +
                                                pipeline::format_number(opt.bridge_offset_mm) +
                                                " mm): straps was run with another --gap-mm, --bridge-offset-mm, respirator, "
                                                "head or landmarks file than assemble was given");
    std::string name = b.name;
    if (name.rfind("strap_", 0) == 0) name = name.substr(6);  // strap_top_attach_left → top_attach_left
    out.blocks.push_back(Block{"attach_" + name.substr(0, name.find("_attach")) + name.substr(name.find("_attach") + 7),
                               0, 1, {rbase + best}});
  }
  // Checks: nothing of the straps inside the head, no two bodies' faces crossing.
  internal::TriangleTree ht(head.nodes, head_surface(head));
  r.strap_gap_mm = 1e300;
  for (const auto& p : straps.nodes) r.strap_gap_mm = std::min(r.strap_gap_mm, ht.signed_distance(p));
  FeModel check;
  check.nodes = out.nodes;
  check.blocks.push_back(Block{"head", 2, 3, {}});
  for (const auto& t : head_surface(head)) check.blocks[0].conn.insert(check.blocks[0].conn.end(), t.begin(), t.end());
  for (std::size_t i = head.blocks.size(); i < out.blocks.size(); ++i)
    if (out.blocks[i].dim >= 2) check.blocks.push_back(out.blocks[i]);
  std::vector<std::array<int, 3>> faces;
  std::vector<std::pair<int, int>> owner;
  layering::internal::element_faces(check, &faces, &owner);
  std::set<std::string> crossing;  // which groups cross, for the error message
  for (auto [a, b] : layering::internal::intersecting_triangles(check.nodes, faces)) {
    ++r.intersecting_pairs;
    const std::string na = check.blocks[owner[a].first].name, nb = check.blocks[owner[b].first].name;
    crossing.insert(std::min(na, nb) + "/" + std::max(na, nb));
  }
  std::string groups;
  for (const auto& c : crossing) groups += " " + c;
  for (const Block& b : out.blocks) {
    if (b.nodes_per_elem == 6) r.wedges += b.size();
    if (b.nodes_per_elem == 4) r.quads += b.size();
  }
  r.nodes = out.nodes.size();
  if (report) *report = r;
  // place_respirator leaves the gap within [gap, gap + 0.001] mm (its bisection): 0.01 mm under the
  // gap asked means the placement itself went wrong.
  if (r.intersecting_pairs || r.gap_mm < opt.gap_mm - 0.01 || r.strap_gap_mm <= 0)
    throw pipeline::algorithm_failed("placement", "initial penetration: " + std::to_string(r.intersecting_pairs) +
                                                     " face pairs intersect (" + groups + " ), gap " + pipeline::format_number(r.gap_mm) +
                                                     " mm, strap gap " + pipeline::format_number(r.strap_gap_mm) + " mm");
  return out;
}

void require_straps_clear_for_thickness(double strap_gap_mm, double strap_thickness_mm, const std::string& straps_path) {
  if (strap_gap_mm >= strap_thickness_mm / 2) return;
  throw pipeline::bad_input(straps_path, "the straps lie " + pipeline::format_number(std::round(strap_gap_mm * 100) / 100) +
                                             " mm off the skin, under half the " + pipeline::format_number(strap_thickness_mm) +
                                             " mm of --strap-thickness-mm: their shells would start inside the head (straps "
                                             "laid for a thinner strap? give straps --thickness-mm " +
                                             pipeline::format_number(strap_thickness_mm) + ")");
}

}  // namespace meshing
