#include "layering/internal/segment_landmarks.h"

#include "pipeline/error.h"
#include "pipeline/read_landmarks.h"

namespace layering::internal {

HeadLandmarks segment_landmarks(const std::map<std::string, pipeline::Landmark>& lm, const std::string& path) {
  auto point = [&](const char* name) -> Vec3 {
    const auto it = lm.find(name);
    if (it == lm.end()) throw pipeline::bad_input(path, std::string("landmark ") + name + " missing");
    const Eigen::Vector3d& p = it->second.position;
    return {p.x(), p.y(), p.z()};
  };
  HeadLandmarks s;
  s.sellion = point("sellion");
  s.pronasale = point("pronasale");
  s.menton = point("menton");
  s.zygion_left = point("zygion_left");
  s.zygion_right = point("zygion_right");
  s.tragion_left = point("tragion_left");
  s.tragion_right = point("tragion_right");
  s.gonion_left = point("gonion_left");
  s.gonion_right = point("gonion_right");
  return s;
}

HeadLandmarks read_segment_landmarks(const std::string& path) {
  return segment_landmarks(pipeline::read_landmarks(path, pipeline::head_landmark_names()), path);
}

}  // namespace layering::internal
