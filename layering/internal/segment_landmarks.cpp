#include "layering/internal/segment_landmarks.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "pipeline/error.h"
#include "pipeline/read_json.h"

namespace layering::internal {

namespace {

Vec3 point(const nlohmann::json& lm, const std::string& path, const std::string& name) {
  if (!lm.contains(name) || !lm[name].is_object() || !lm[name].contains("position"))
    throw pipeline::bad_input(path, "landmark '" + name + "' missing");
  const auto& p = lm[name]["position"];
  if (!p.is_array() || p.size() != 3)
    throw pipeline::bad_input(path, "landmark '" + name + "': position is not [x, y, z]");
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!p[i].is_number() || !std::isfinite(p[i].get<double>()))
      throw pipeline::bad_input(path, "landmark '" + name + "': non-finite coordinate");
    v[i] = p[i].get<double>();
  }
  return v;
}

}  // namespace

HeadLandmarks read_segment_landmarks(const std::string& path) {
  const nlohmann::json j = pipeline::read_json(path);
  if (!j.is_object() || !j.contains("landmarks") || !j["landmarks"].is_object())
    throw pipeline::bad_input(path, "no \"landmarks\" object");
  const auto& lm = j["landmarks"];
  HeadLandmarks s;
  s.sellion = point(lm, path, "sellion");
  s.pronasale = point(lm, path, "pronasale");
  s.menton = point(lm, path, "menton");
  s.zygion_left = point(lm, path, "zygion_left");
  s.zygion_right = point(lm, path, "zygion_right");
  s.tragion_left = point(lm, path, "tragion_left");
  s.tragion_right = point(lm, path, "tragion_right");
  s.gonion_left = point(lm, path, "gonion_left");
  s.gonion_right = point(lm, path, "gonion_right");
  if (s.zygion_left[0] <= 0 || s.zygion_right[0] >= 0 || s.gonion_left[0] <= 0 ||
      s.gonion_right[0] >= 0 || s.tragion_left[0] <= 0 || s.tragion_right[0] >= 0)
    throw pipeline::bad_input(path, "left landmarks must have x > 0 and right ones x < 0 "
                                    "(subject's left is +x): is the head aligned?");
  if (s.menton[1] >= s.sellion[1] - 30.0)
    throw pipeline::bad_input(path, "menton y " + pipeline::format_number(s.menton[1]) +
                                        " not at least 30 mm below sellion y " +
                                        pipeline::format_number(s.sellion[1]) + ": is the head aligned (y up)?");
  if (s.pronasale[1] >= s.sellion[1] || s.pronasale[1] <= s.menton[1])
    throw pipeline::bad_input(path, "pronasale y " + pipeline::format_number(s.pronasale[1]) +
                                        " not between menton and sellion: are the landmarks swapped?");
  return s;
}

}  // namespace layering::internal
