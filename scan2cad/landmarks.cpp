// Landmarks file I/O and measures; see landmarks.h. Detection is in internal/landmarks_detect.cpp.
#include "scan2cad/landmarks.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "pipeline/error.h"
#include "pipeline/read_json.h"

namespace scan2cad {

const std::vector<std::string>& required_landmarks() {
  static const std::vector<std::string> names = {"sellion",      "pronasale",     "menton",
                                                 "zygion_left",  "zygion_right",  "tragion_left",
                                                 "tragion_right", "gonion_left",  "gonion_right"};
  return names;
}

static double dist(const Landmarks& l, const char* a, const char* b) {
  return (l.points.at(a).position - l.points.at(b).position).norm();
}
double face_length(const Landmarks& l) { return dist(l, "menton", "sellion"); }
double face_width(const Landmarks& l) { return dist(l, "zygion_left", "zygion_right"); }

std::vector<std::string> guessed_landmarks(const Landmarks& l, double below) {
  std::vector<std::string> guessed;
  for (const auto& [name, p] : l.points)
    if (p.confidence < below) guessed.push_back(name);
  return guessed;
}

std::string landmarks_json(const Landmarks& l) {
  nlohmann::json j;
  j["frame"] = "x lateral (+x = subject's left), y up, z out of the face; mm";
  j["source"] = l.source;
  for (const auto& [name, p] : l.points)
    j["landmarks"][name] = {{"position", {p.position.x(), p.position.y(), p.position.z()}},
                            {"confidence", p.confidence}};
  j["measures_mm"]["face_length"] = face_length(l);
  j["measures_mm"]["face_width"] = face_width(l);
  j["measures_mm"]["bitragion_breadth"] = dist(l, "tragion_left", "tragion_right");
  j["measures_mm"]["bigonial_breadth"] = dist(l, "gonion_left", "gonion_right");
  return j.dump(2) + "\n";
}

Landmarks read_landmarks(const std::string& path) {
  const nlohmann::json j = pipeline::read_json(path);
  if (!j.is_object() || !j.contains("landmarks") || !j["landmarks"].is_object())
    throw pipeline::bad_input(path, "no \"landmarks\" object");
  Landmarks l;
  l.source = "user";
  for (const auto& [name, v] : j["landmarks"].items()) {
    const std::string what = "landmark " + name;
    if (!v.is_object() || !v.contains("position") || !v["position"].is_array() || v["position"].size() != 3)
      throw pipeline::bad_input(path, what + ": \"position\" must be 3 numbers");
    Landmark p;
    for (int k = 0; k < 3; ++k) {
      if (!v["position"][k].is_number()) throw pipeline::bad_input(path, what + ": position is not numeric");
      p.position[k] = v["position"][k].get<double>();
    }
    if (!p.position.allFinite()) throw pipeline::bad_input(path, what + ": non-finite position");
    // Optional (1 when absent); a value that is there must be a number, not silently 1.
    if (v.contains("confidence") && !v["confidence"].is_number())
      throw pipeline::bad_input(path, what + ": confidence " + v["confidence"].dump() + ", expected a number 0..1");
    p.confidence = v.contains("confidence") ? v["confidence"].get<double>() : 1.0;
    if (!(p.confidence >= 0.0 && p.confidence <= 1.0))
      throw pipeline::bad_input(path, what + ": confidence " + pipeline::format_number(p.confidence) + ", expected 0..1");
    l.points[name] = p;
  }
  for (const auto& name : required_landmarks())
    if (!l.points.count(name)) throw pipeline::bad_input(path, "missing landmark " + name);
  for (const auto& [name, p] : l.points) {
    const bool left = name.size() > 5 && name.compare(name.size() - 5, 5, "_left") == 0;
    const bool right = name.size() > 6 && name.compare(name.size() - 6, 6, "_right") == 0;
    if ((left && p.position.x() <= 0.0) || (right && p.position.x() >= 0.0))
      throw pipeline::bad_input(path, "landmark " + name + ": x = " + pipeline::format_number(p.position.x()) +
                                          ", expected " + (left ? "> 0 (subject's left is +x)" : "< 0 (subject's right is -x)"));
  }
  return l;
}

}  // namespace scan2cad
