#pragma once
/// Reading the landmarks JSON (format: written by `landmarks`, or supplied by the user) for
/// `segment`. Only the points segmentation needs are kept.
#include <string>

#include "layering/segment.h"

namespace layering::internal {

/// Reads the landmarks file with pipeline::read_landmarks (which checks positions, confidences and
/// sides) and keeps the nine points segmentation needs.
/// @throws pipeline::Error(bad_input) naming `path` as that reader does, if one of the nine is
///         missing, if the menton is not at least 30 mm below the sellion (a head not y-up), or if
///         the pronasale is not between them in y (landmarks swapped).
HeadLandmarks read_segment_landmarks(const std::string& path);

}  // namespace layering::internal
