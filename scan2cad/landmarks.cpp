// Landmarks file I/O and measures; see landmarks.h. Detection is in internal/landmarks_detect.cpp.
#include "scan2cad/landmarks.h"

#include <cmath>

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
  if (l.source == "detected") j["window_scale"] = l.window_scale;
  for (const auto& [name, p] : l.points)
    j["landmarks"][name] = {{"position", {p.position.x(), p.position.y(), p.position.z()}},
                            {"confidence", p.confidence}};
  j["measures_mm"]["face_length"] = face_length(l);
  j["measures_mm"]["face_width"] = face_width(l);
  j["measures_mm"]["bitragion_breadth"] = dist(l, "tragion_left", "tragion_right");
  j["measures_mm"]["bigonial_breadth"] = dist(l, "gonion_left", "gonion_right");
  return j.dump(2) + "\n";
}

std::vector<std::string> user_landmark_notes(const Landmarks& user, const pipeline::SurfaceMesh& head,
                                             const std::map<std::string, double>& off_surface_mm) {
  constexpr double note_off_surface_mm = 2, note_from_detected_mm = 15;
  const auto one_decimal = [](double mm) { return pipeline::format_number(std::round(mm * 10) / 10); };
  std::vector<std::string> notes;
  for (const auto& [name, d] : off_surface_mm)
    if (d > note_off_surface_mm)
      notes.push_back("landmark " + name + " is " + one_decimal(d) + " mm off the head's surface; kept where it is");
  try {
    const Landmarks detected = detect_landmarks(head);
    for (const auto& [name, point] : user.points)
      if (const auto it = detected.points.find(name); it != detected.points.end())
        if (const double d = (point.position - it->second.position).norm(); d > note_from_detected_mm)
          notes.push_back("landmark " + name + " is " + one_decimal(d) + " mm from where detection puts it on this head (confidence " +
                          pipeline::format_number(std::round(it->second.confidence * 100) / 100) + "): another head's landmarks?");
  } catch (const pipeline::Error& e) {
    if (e.kind != pipeline::ErrorKind::algorithm) throw;  // detection found no face: nothing to compare
  }
  return notes;
}

Landmarks read_landmarks(const std::string& path) {
  Landmarks l;
  l.source = "user";
  l.points = pipeline::read_landmarks(path, required_landmarks());
  return l;
}

}  // namespace scan2cad
