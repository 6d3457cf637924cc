#include "data/generator/generate_scan.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "data/generator/head_model.h"
#include "data/generator/respirator_model.h"
#include "pipeline/atomic_write.h"
#include "pipeline/error.h"
#include "pipeline/read_scan.h"

namespace generator {

namespace {

pipeline::Error usage(const std::string& msg) { return pipeline::Error(pipeline::ErrorKind::usage, msg); }

}  // namespace

GeneratedScan generate_scan(const GenerateRequest& rq) {
  const bool from_mesh = !rq.mesh_path.empty();
  if (!from_mesh && rq.kind.empty())
    throw usage("give either --from-mesh PATH or --kind head|respirator (with --id and --params)");
  // With a mesh, --kind says what it is (its size guesses its unit) and --id/--params mean
  // nothing: both had been ignored without a word, and a respirator-sized mesh was refused as
  // "an object of another kind (see --kind)" by a program that refused --kind beside it.
  if (from_mesh && (!rq.id.empty() || !rq.params_path.empty()))
    throw usage("--from-mesh scans the mesh given: --id and --params are for generated models");
  if (!from_mesh && rq.unit != "auto") throw usage("--unit is for --from-mesh: the generated models are in mm");
  Triangles tri;
  std::vector<Hole> model_holes;
  std::string rim_note, unit_note;
  if (from_mesh) {
    pipeline::ScanReadOptions ropt;
    ropt.unit = pipeline::parse_unit(rq.unit);
    const std::string object = rq.kind.empty() ? "head" : rq.kind;
    ropt.expected_size_mm = pipeline::expected_extent_mm(object);
    const pipeline::Scan scan = pipeline::read_scan(rq.mesh_path, ropt);
    if (!scan.is_mesh) throw pipeline::bad_input(rq.mesh_path, "is a point cloud, expected a mesh to scan");
    // As reconstruct does: a forced unit is checked, and the unit taken is said (a mesh in cm or m
    // was scaled to mm without a word).
    if (ropt.unit != pipeline::Unit::automatic)
      pipeline::require_forced_unit_plausible(rq.mesh_path, scan.unit, scan.extent_mm, object, ropt.expected_size_mm);
    unit_note = rq.mesh_path + ": " +
                pipeline::describe_unit(scan.unit, ropt.unit == pipeline::Unit::automatic, scan.extent_mm, object,
                                        ropt.expected_size_mm);
    tri = triangles_of(scan.soup);
  } else if (rq.id.empty() || rq.params_path.empty()) {
    throw usage("--kind " + rq.kind + " needs --id and --params");
  } else if (rq.kind == "head") {
    const HeadShape head(read_head_params(rq.params_path, rq.id));
    tri = head.mesh(7);
    model_holes = head.scanner_holes();
  } else if (rq.kind == "respirator") {
    HeadParams face;
    const RespiratorParams p = read_respirator_params(rq.params_path, rq.id, &face);
    RimSize rim;
    tri = make_respirator(p, HeadShape(face), &rim);
    using pipeline::format_number;
    const auto mm = [](double v) { return format_number(std::round(10 * v) / 10); };
    rim_note = "rim " + mm(rim.width) + " x " + mm(rim.height) + " mm as built (design " + mm(p.width) + " x " +
               mm(p.height) + ")";
    if (rim.width < p.width - 2 || rim.height < p.height - 2)
      rim_note += ": the rim stays on the front of the average face, between " + mm(p.nose_drop) +
                  " mm below its sellion and 2 mm above its menton";
  } else {
    throw usage("--kind: expected 'head' or 'respirator', got '" + rq.kind + "'");
  }

  ScanOptions opt;
  const double area = surface_area(tri);
  opt.points = rq.points > 0 ? std::size_t(rq.points)
                             : std::size_t(std::llround(area / (rq.spacing_mm * rq.spacing_mm)));
  // --points is bounded through the spacing it gives on this surface, as --spacing-mm is: a few
  // points (e.g. -n 1) made a "scan" that only reconstruct refused.
  const double spacing_mm = std::sqrt(area / double(opt.points));
  if (rq.points > 0 && spacing_mm > max_scan_spacing_mm)
    throw usage("--points " + std::to_string(rq.points) + " spaces the points " + pipeline::format_number(spacing_mm) +
                " mm apart on this surface of " + pipeline::format_number(area) + " mm2: at most " +
                pipeline::format_number(max_scan_spacing_mm) + " mm, as --spacing-mm");
  opt.noise_mm = rq.noise_mm;
  opt.noise_direction = rq.noise_direction;
  opt.outliers.fraction = rq.outlier_fraction;
  opt.random_holes = rq.random_holes >= 0 ? rq.random_holes : (from_mesh ? 0 : 1);
  opt.hole_diameter_min_mm = rq.hole_diameter_min_mm;
  opt.hole_diameter_max_mm = rq.hole_diameter_max_mm;
  if (!rq.no_model_holes) opt.holes = model_holes;

  GeneratedScan out;
  Rng rng(rq.seed);
  out.cloud = scan_surface(tri, opt, rng, &out.holes);
  if (rq.want_clean_mesh) out.clean_mesh = surface_mesh_of(tri);
  out.rim_note = rim_note;
  out.unit_note = unit_note;
  return out;
}

void parse_hole_diameters(const std::string& text, double* min_mm, double* max_mm) {
  const auto colon = text.find(':');
  const std::string a = text.substr(0, colon);
  const std::string b = colon == std::string::npos ? a : text.substr(colon + 1);
  auto num = [&](const std::string& s) {
    std::size_t pos = 0;
    double v = NAN;
    try {
      v = std::stod(s, &pos);
    } catch (...) {
      pos = 0;
    }
    // Decimal only, as every other number option: stod took 0x10:0x14 as 16:20.
    if (s.find_first_not_of("0123456789.eE+-") != std::string::npos) pos = 0;
    if (pos == 0 || pos != s.size() || !std::isfinite(v) || v <= 0)
      throw usage("--hole-diameter-mm: expected MIN:MAX in mm (positive numbers), got '" + text + "'");
    return v;
  };
  *min_mm = num(a);
  *max_mm = num(b);
  if (*min_mm > *max_mm)
    throw usage("--hole-diameter-mm: MIN > MAX in '" + text + "'");
  // A hole narrower than a scanner's point spacing (0.5-1 mm) removes a point or none: not a hole.
  constexpr double min_hole_mm = 1;
  if (*min_mm < min_hole_mm)
    throw usage("--hole-diameter-mm: MIN " + pipeline::format_number(*min_mm) + " mm in '" + text +
                "' is narrower than " + pipeline::format_number(min_hole_mm) + " mm, a scanner's point spacing");
  // A scanner leaves holes of a few mm to a few cm (under the chin, in the ears); one wider than
  // a face (~140 mm) is a slip of unit or of a digit, and failed only after the sampling.
  constexpr double max_hole_mm = 100;
  if (*max_mm > max_hole_mm)
    throw usage("--hole-diameter-mm: MAX " + pipeline::format_number(*max_mm) + " mm in '" + text + "' is wider than " +
                pipeline::format_number(max_hole_mm) + " mm");
}

NoiseDirection parse_noise_direction(const std::string& text) {
  if (text == "normal") return NoiseDirection::normal;
  if (text == "isotropic") return NoiseDirection::isotropic;
  throw usage("--noise-direction: expected 'normal' or 'isotropic', got '" + text + "'");
}

void write_holes_json(const std::string& path, const std::vector<Hole>& holes) {
  nlohmann::json j;
  j["frame"] = "the scan's own coordinates (those of --out); mm";
  j["holes"] = nlohmann::json::array();
  for (const Hole& h : holes)
    j["holes"].push_back({{"centre", {h.centre.x(), h.centre.y(), h.centre.z()}},
                          {"normal", {h.normal.x(), h.normal.y(), h.normal.z()}},
                          {"radius_mm", h.radius_mm}});
  pipeline::write_text_atomic(path, j.dump(2) + "\n");
}

}  // namespace generator
