// meshing::make_deck: the two solver decks of the paper's simulation (solve/README.md format).
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

#include "meshing/assemble.h"
#include "meshing/internal/assemble_geometry.h"
#include "meshing/straps.h"
#include "pipeline/error.h"
#include "pipeline/read_json.h"
#include "pipeline/units.h"

namespace meshing {

namespace {

// The path of a strap end from `from` to its attachment point `to`, kept `clearance_mm` off the
// skin: the chord between them cuts through the head (a strap end beside the temple pulled to a
// rim point in front of the cheek passes under the skin), and a prescribed node cannot be pushed
// out by contact, so stage I stopped on penetration after 14 ms. Waypoints every ~2 mm along the
// chord are lifted to the clearance along the closest skin face's normal; the attachment itself
// (on the respirator, 3 mm off the skin) stays as it is. Times follow the arc length, so the end
// moves at constant speed.
struct EndPath {
  std::vector<Eigen::Vector3d> points;  ///< from `from` to `to`
  std::vector<double> arc_mm;           ///< cumulative length at each point
};

EndPath end_path(const internal::TriangleTree& skin, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                 double clearance_mm) {
  const int n = std::max(2, int(std::ceil((to - from).norm() / 2.0)));
  EndPath p;
  for (int i = 0; i <= n; ++i) {
    Eigen::Vector3d q = from + (to - from) * (double(i) / n), closest, normal;
    if (i > 0 && i < n && skin.signed_distance(q, &closest, &normal) < clearance_mm) q = closest + clearance_mm * normal;
    const double step = p.points.empty() ? 1.0 : (q - p.points.back()).norm();
    if (step < 1e-6 && i < n) continue;  // two chord points lifted onto one: the curve's times must increase
    p.arc_mm.push_back(p.points.empty() ? 0.0 : p.arc_mm.back() + step);
    p.points.push_back(q);
  }
  if (p.arc_mm.back() <= 0) {  // the end is already at its attachment: it stays where it is
    p.points = {from, to};
    p.arc_mm = {0.0, 1.0};
  }
  return p;
}

}  // namespace

// Before this check a bad value (E "x", nu 0.7, a density in g/cm³) went into the decks with
// exit 0, and a missing one ended assemble as an internal error.
nlohmann::json deck_materials(const nlohmann::json& mat) {
  using nlohmann::json;
  if (!mat.is_object() || !mat.contains("materials") || !mat["materials"].is_object())
    throw pipeline::bad_input("materials", "expected an object of materials");
  // Keys with defaults ("rigid", "contact", "damping"): a misspelt one ("rigd": true) was read as
  // absent, and the bone went into the decks as soft tissue.
  if (const std::string key = pipeline::first_unknown_key(
          mat, {"materials", "head_layers_mm", "respirator_layers_mm", "contact", "damping"});
      !key.empty())
    throw pipeline::bad_input(key, "unknown key");
  json out = json::object();
  for (auto& [k, v] : mat["materials"].items()) {
    if (k[0] == '_') continue;
    const std::string w = "materials." + k;
    if (!v.is_object()) throw pipeline::bad_input(w, "expected an object");
    if (const std::string key = pipeline::first_unknown_key(v, pipeline::material_keys); !key.empty())
      throw pipeline::bad_input(w + "." + key, "unknown key");
    auto number = [&](const char* field) {
      if (!v.contains(field) || !v[field].is_number()) throw pipeline::bad_input(w + "." + field, "expected a number");
      return v[field].get<double>();
    };
    const double density = number("density"), E = number("E"), nu = number("nu");
    if (const std::string why = pipeline::why_material_unusable(density, E, nu); !why.empty())
      throw pipeline::bad_input(w, why);
    if (v.contains("rigid") && !v["rigid"].is_boolean()) throw pipeline::bad_input(w + ".rigid", "expected true or false");
    json x = {{"density", density}, {"E", E}, {"nu", nu}};
    if (v.value("rigid", false)) x["rigid"] = true;
    out[k] = x;
  }
  return out;
}

namespace {

// `mat[section][key]` of data/materials.json, or `fallback` when the file has neither; a value
// that is there must be a number `valid` accepts.
double optional_setting(const nlohmann::json& mat, const char* section, const char* key, double fallback,
                        bool (*valid)(double), const std::string& expected) {
  if (!mat.contains(section)) return fallback;
  const auto& s = mat[section];
  if (!s.is_object()) throw pipeline::bad_input(section, "expected an object");
  // each section holds one setting ("penalty_scale": 0.1, misspelt, had given the default)
  if (const std::string other = pipeline::first_unknown_key(s, {key}); !other.empty())
    throw pipeline::bad_input(std::string(section) + "." + other, "unknown key");
  if (!s.contains(key)) return fallback;
  const auto& v = s[key];
  if (!v.is_number() || !valid(v.get<double>()))
    throw pipeline::bad_input(std::string(section) + "." + key, "expected " + expected);
  return v.get<double>();
}

}  // namespace

double stage1_damping_alpha(const nlohmann::json& mat) {
  return optional_setting(
      mat, "damping", "stage1_alpha_per_ms", 0.5,
      [](double a) { return a >= 0 && a <= pipeline::max_damping_alpha_per_ms; },
      "a number in [0, " + pipeline::format_number(pipeline::max_damping_alpha_per_ms) + "] [1/ms], as solve takes it");
}

double contact_penalty_scale(const nlohmann::json& mat) {
  // The range solve accepts (solve/contact.h), so a bad value stops here, before the decks.
  return optional_setting(
      mat, "contact", "penalty_scale", 0.1, [](double s) { return s > 0 && s <= 1; },
      "a number in (0, 1] (s of the contact stiffness k = s m / dt^2)");
}

nlohmann::json make_deck(const layering::FeModel& m, const nlohmann::json& mat, int stage, double strap_t,
                         const std::string& stage1_state) {
  using nlohmann::json;
  json d;
  // The model the deck is made for, which solve checks (solve/README.md): a case's deck run on
  // another case's model ran 10 minutes before stage II's ties failed.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& p : m.nodes) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  d["model_check"] = {{"nodes", m.nodes.size()}, {"bounds_mm", {{lo.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), hi.z()}}}};
  d["materials"] = deck_materials(mat);
  // Part groups: "<part>_<tissue>" wedges of the head, respirator layers, straps, back of head.
  auto material_of = [&](const std::string& g) -> std::string {
    if (g == "respirator_seal") return "seal_layer";
    if (g == "respirator_outer") return "outer_layer";
    if (g == "back_of_head") return "back_of_head";
    if (g == "strap_top" || g == "strap_bottom") return "strap";
    const auto u = g.rfind('_');
    return u == std::string::npos ? "" : g.substr(u + 1);
  };
  json parts = json::array(), fixed = json::array(), presc = json::array(), ties = json::array();
  std::vector<std::string> bones, head_parts, resp_parts;
  for (const auto& b : m.blocks) {
    const bool solid = b.dim == 3, shell = b.dim == 2 && (b.name == "back_of_head" || b.name.rfind("strap_", 0) == 0);
    if (!solid && !shell) continue;
    const std::string mt = material_of(b.name);
    if (!d["materials"].contains(mt))
      throw pipeline::bad_input("model", "group " + b.name + ": no material \"" + mt + "\" in materials.json");
    json p = {{"group", b.name}, {"material", mt}};
    // back_of_head is a rigid shell, fixed in both stages: its thickness sets only its mass, which
    // enters only the contact stiffness of what touches it (through the reduced mass, contact.h).
    // 1 mm: a thickness the solver requires of every membrane part, not a measured one.
    if (shell) p["thickness"] = b.name == "back_of_head" ? 1.0 : strap_t;
    parts.push_back(p);
    if (mt == "bone" || b.name == "back_of_head") bones.push_back(b.name);
    else if (b.name.rfind("respirator_", 0) == 0) resp_parts.push_back(b.name);
    else if (b.name.rfind("strap_", 0) != 0) head_parts.push_back(b.name);
  }
  d["parts"] = parts;
  for (const auto& g : bones) fixed.push_back({{"group", g}, {"dofs", "xyz"}});
  json contact = json::array();
  const double penalty_scale = contact_penalty_scale(mat);
  for (const char* s : {"strap_top", "strap_bottom"})
    if (m.find(s))
      contact.push_back({{"name", std::string(s) + "_on_head"}, {"slave", s}, {"master", "head_skin"},
                         {"penalty_scale", penalty_scale}});
  // The mean of a strap end line's element nodes (its middle node counts twice: both line elements hold it).
  const auto centre_of = [&](const layering::Block& end) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : end.conn) c += m.nodes[v] / double(end.conn.size());
    return c;
  };
  const double alpha = stage1_damping_alpha(mat);
  if (stage == 1) {
    // Head and respirator held; each strap end moves with constant speed to its attachment
    // point in 0–100 ms, around the head (end_path), and stays there to 200 ms (paper Fig. 6).
    for (const auto& g : head_parts) fixed.push_back({{"group", g}, {"dofs", "xyz"}});
    for (const auto& g : resp_parts) fixed.push_back({{"group", g}, {"dofs", "xyz"}});
    const internal::TriangleTree skin(m.nodes, head_surface(m));
    for (const char* s : {"top", "bottom"})
      for (const char* side : {"left", "right"}) {
        const auto* end = m.find(std::string("strap_") + s + "_end_" + side);
        const auto* att = m.find(std::string("attach_") + s + "_" + side);
        if (!end || !att) continue;
        const Eigen::Vector3d c = centre_of(*end);
        const EndPath path = end_path(skin, c, m.nodes[att->conn[0]], strap_clearance_mm + 0.5 * strap_t);
        for (int k = 0; k < 3; ++k) {
          json curve = json::array();
          for (std::size_t i = 0; i < path.points.size(); ++i)
            curve.push_back({i + 1 == path.points.size() ? 100.0 : 100.0 * path.arc_mm[i] / path.arc_mm.back(),
                            path.points[i][k] - c[k]});
          curve.push_back({200.0, path.points.back()[k] - c[k]});
          presc.push_back({{"group", end->name}, {"type", "displacement"}, {"dof", std::string(1, "xyz"[k])},
                           {"curve", curve}});
        }
      }
    d["prescribed"] = presc;
    d["control"] = {{"end_time", 200.0}, {"damping_alpha", alpha}, {"output_interval", 20.0}};
    d["output"] = {{"history_groups", json::array()}};
    for (std::size_t i = 0; i < presc.size(); i += 3)  // one history per strap end, not per direction
      d["output"]["history_groups"].push_back(presc[i]["group"]);
  } else {
    // Respirator released, straps tied to it at the attachment points; bone and back of head fixed.
    for (const char* s : {"top", "bottom"})
      for (const char* side : {"left", "right"}) {
        const std::string end = std::string("strap_") + s + "_end_" + side, att = std::string("attach_") + s + "_" + side;
        const auto* end_group = m.find(end);
        if (!end_group || !m.find(att)) continue;
        // Stage I brings the end line's middle onto the attachment node: its other nodes end up
        // as far from it as they are from their middle (half the strap's width), and 2 mm more
        // are allowed for the end's turn along the path. 5 mm at least (the 6 mm strap's 3 + 2).
        const Eigen::Vector3d c = centre_of(*end_group);
        double half_mm = 0;
        for (int v : end_group->conn) half_mm = std::max(half_mm, (m.nodes[v] - c).norm());
        ties.push_back({{"name", end + "_to_respirator"}, {"group_a", end}, {"group_b", att},
                        {"tolerance", std::max(5.0, half_mm + 2.0)}});
      }
    d["ties"] = ties;
    contact.push_back({{"name", "respirator_on_face"}, {"slave", "respirator_inner"}, {"master", "head_skin"},
                       {"penalty_scale", penalty_scale}});
    d["initial_state"] = {{"file", stage1_state}, {"reset_time", true}, {"reset_velocity", true}};
    d["control"] = {{"end_time", 150.0}, {"damping_alpha", alpha}, {"output_interval", 10.0}};
    d["output"] = {{"history_groups", json::array()}};
    for (const auto& t : ties) d["output"]["history_groups"].push_back(t["group_a"]);
  }
  d["fixed"] = fixed;
  d["contact"] = contact;
  return d;
}

}  // namespace meshing
