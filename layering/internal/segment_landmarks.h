#pragma once
/// Reading the landmarks JSON (format: written by `landmarks`, or supplied by the user) for
/// `segment`. Only the points segmentation needs are kept.
#include <string>

#include "layering/segment.h"

namespace layering::internal {

/// Reads the landmarks file.
/// @throws pipeline::Error(bad_input) naming `path` if it is missing, not JSON, lacks one of the
///         points above, has non-finite coordinates, or puts a left landmark at x < 0 / a right
///         one at x > 0 (mirrored frame) or the menton above the sellion.
HeadLandmarks read_segment_landmarks(const std::string& path);

}  // namespace layering::internal
