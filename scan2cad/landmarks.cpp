// Landmarks file I/O and measures; see landmarks.h. Detection is in internal/landmarks_detect.cpp.
#include "scan2cad/landmarks.h"

#include <nlohmann/json.hpp>

#include "pipeline/error.h"

namespace scan2cad {

const std::vector<std::string>& required_landmarks() { return pipeline::head_landmark_names(); }

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

void require_adult_face(const Landmarks& l, const std::string& path) {
  const double length_mm = face_length(l), width_mm = face_width(l);
  if (length_mm >= min_face_length_mm && length_mm <= max_face_length_mm && width_mm >= min_face_width_mm &&
      width_mm <= max_face_width_mm)
    return;
  throw pipeline::bad_input(path, "face length " + pipeline::format_number(length_mm) + " mm and width " +
                                      pipeline::format_number(width_mm) + " mm, outside any adult's (" +
                                      pipeline::format_number(min_face_length_mm) + "-" +
                                      pipeline::format_number(max_face_length_mm) + " and " +
                                      pipeline::format_number(min_face_width_mm) + "-" +
                                      pipeline::format_number(max_face_width_mm) +
                                      " mm): a head at another scale (its unit?), or landmarks misplaced");
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
  Landmarks l;
  l.source = "user";
  l.points = pipeline::read_landmarks(path, required_landmarks());
  return l;
}

}  // namespace scan2cad
