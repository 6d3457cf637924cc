#pragma once
/// Reading the landmarks JSON (format: written by `landmarks`, or supplied by the user) for
/// `segment`. Only the points segmentation needs are kept.
#include <map>
#include <string>

#include "layering/segment.h"
#include "pipeline/read_landmarks.h"

namespace layering::internal {

/// The nine points segmentation needs, from landmarks read by pipeline::read_landmarks (which
/// checks positions, confidences, sides and the profile's order in y) from `path`.
/// @throws pipeline::Error(bad_input) naming `path` if one of the nine is missing.
HeadLandmarks segment_landmarks(const std::map<std::string, pipeline::Landmark>& landmarks, const std::string& path);

/// segment_landmarks of the file `path`, read with pipeline::read_landmarks.
/// @throws pipeline::Error(bad_input) naming `path` as that reader does, or as segment_landmarks.
HeadLandmarks read_segment_landmarks(const std::string& path);

}  // namespace layering::internal
