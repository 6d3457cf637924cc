#include "pipeline/read_landmarks.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>

#include "pipeline/error.h"
#include "pipeline/read_json.h"

namespace pipeline {

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() > tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

Landmark landmark_of(const nlohmann::json& v, const std::string& path, const std::string& what) {
  // "confidence" is optional: a misspelt one ("confidnce": 0.2) was read as absent, as 1. Named
  // first, so that "Position" is named too (it had got '"position" is not [x, y, z]').
  if (v.is_object())
    if (const std::string key = first_unknown_key(v, {"position", "confidence"}); !key.empty())
      throw bad_input(path, what + ": unknown key \"" + key + "\" (a landmark has \"position\" and \"confidence\")");
  if (!v.is_object() || !v.contains("position") || !v["position"].is_array() || v["position"].size() != 3)
    throw bad_input(path, what + ": \"position\" is not [x, y, z]");
  Landmark l;
  for (int k = 0; k < 3; ++k) {
    const auto& c = v["position"][std::size_t(k)];
    if (!c.is_number() || !std::isfinite(c.get<double>()))
      throw bad_input(path, what + ": a coordinate is not a finite number");
    // 1e308 passed, and the exact distance predicates of the surface check then died of a
    // floating-point trap (in GMP); see max_landmark_coordinate_mm.
    if (std::abs(c.get<double>()) > max_landmark_coordinate_mm)
      throw bad_input(path, what + ": coordinate " + format_number(c.get<double>()) + " is beyond +-" +
                                format_number(max_landmark_coordinate_mm) + " mm (not a point on a head in mm)");
    l.position[k] = c.get<double>();
  }
  if (v.contains("confidence")) {
    // A value that is there must be a number: "high" or null was read as 1.
    const auto& c = v["confidence"];
    if (!c.is_number()) throw bad_input(path, what + ": confidence " + c.dump() + ", expected a number 0..1");
    l.confidence = c.get<double>();
    if (!(l.confidence >= 0.0 && l.confidence <= 1.0))
      throw bad_input(path, what + ": confidence " + format_number(l.confidence) + ", expected 0..1");
  }
  return l;
}

}  // namespace

const std::vector<std::string>& head_landmark_names() {
  static const std::vector<std::string> names = {"sellion",      "pronasale",    "menton",
                                                 "zygion_left",  "zygion_right", "tragion_left",
                                                 "tragion_right", "gonion_left", "gonion_right"};
  return names;
}

bool is_head_landmark_name(const std::string& name) {
  const auto& names = head_landmark_names();
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::map<std::string, Landmark> read_landmarks(const std::string& path, const std::vector<std::string>& required) {
  const nlohmann::json j = read_json(path);
  if (!j.is_object() || !j.contains("landmarks") || !j["landmarks"].is_object())
    throw bad_input(path, "no \"landmarks\" object");
  std::map<std::string, Landmark> out;
  for (const auto& [name, v] : j["landmarks"].items()) {
    // Other landmarks are kept (a user's own points), but a stage's name written another way
    // ("Sellion", "Tragion_Left") was kept as another point while the file's real one was used,
    // or reported missing.
    std::string lower = name;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    if (lower != name && is_head_landmark_name(lower))
      throw bad_input(path, "landmark \"" + name + "\": the name is \"" + lower + "\" (lower case)");
    out[name] = landmark_of(v, path, "landmark " + name);
  }
  for (const auto& name : required)
    if (!out.count(name)) throw bad_input(path, "landmark " + name + " missing");
  for (const auto& [name, l] : out) {
    const bool left = ends_with(name, "_left"), right = ends_with(name, "_right");
    if ((left && !(l.position.x() > 0.0)) || (right && !(l.position.x() < 0.0)))
      throw bad_input(path, "landmark " + name + ": x = " + format_number(l.position.x()) + ", expected " +
                                (left ? "> 0 (the subject's left is +x)" : "< 0 (the subject's right is -x)") +
                                ": is the head mirrored, or not aligned?");
  }
  // The profile in y (up): a head upside down, or sellion and menton swapped by hand, passed
  // landmarks --user, straps and assemble (only segment checked it).
  const auto sel = out.find("sellion"), men = out.find("menton"), prn = out.find("pronasale");
  // A file in cm or m was reported as a head not aligned (menton not 30 mm below the sellion).
  if (sel != out.end() && men != out.end()) {
    const double face = (sel->second.position - men->second.position).norm();
    auto adult = [](double mm) { return mm >= 60 && mm <= 200; };
    if (face < 30 && (adult(10 * face) || adult(1000 * face)))
      throw bad_input(path, "sellion and menton are " + format_number(face) + " apart, and no face is under 30 mm: landmarks in " +
                                (adult(10 * face) ? "cm" : "m") + "? (positions are in mm, in align's frame)");
  }
  // The midline: a menton 25 mm to the side was taken, and the respirator placed 12 mm off
  // centre (sweep J). The detected ones lie on x = 0 (align's symmetry plane).
  constexpr double max_midline_x_mm = 10;
  for (const char* name : {"sellion", "pronasale", "menton"})
    if (const auto it = out.find(name); it != out.end() && !(std::abs(it->second.position.x()) <= max_midline_x_mm))
      throw bad_input(path, std::string("landmark ") + name + ": x = " + format_number(it->second.position.x()) +
                                ", expected within " + format_number(max_midline_x_mm) +
                                " mm of the symmetry plane x = 0: is the head aligned, or the point picked off the midline?");
  if (sel != out.end() && men != out.end() && !(men->second.position.y() < sel->second.position.y() - 30.0))
    throw bad_input(path, "menton y " + format_number(men->second.position.y()) + " not at least 30 mm below sellion y " +
                              format_number(sel->second.position.y()) + ": is the head aligned (y up)?");
  if (sel != out.end() && men != out.end() && prn != out.end() &&
      !(prn->second.position.y() < sel->second.position.y() && prn->second.position.y() > men->second.position.y()))
    throw bad_input(path, "pronasale y " + format_number(prn->second.position.y()) +
                              " not between menton and sellion: are the landmarks swapped?");
  // Each side's jaw angle below its ear: a tragion and gonion swapped by hand put the gonion above
  // the cheekbone and cut cheeks 30 % smaller (segment), with exit 0.
  for (const char* side : {"_left", "_right"}) {
    const auto tra = out.find(std::string("tragion") + side), gon = out.find(std::string("gonion") + side);
    if (tra != out.end() && gon != out.end() && !(gon->second.position.y() < tra->second.position.y() - 20.0))
      throw bad_input(path, gon->first + " y " + format_number(gon->second.position.y()) + " not at least 20 mm below " +
                                tra->first + " y " + format_number(tra->second.position.y()) +
                                ": are the landmarks swapped?");
  }
  return out;
}

}  // namespace pipeline
