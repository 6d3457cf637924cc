#pragma once
/// The check that a landmarks file belongs to the surface it is used with: `landmarks --user`
/// (against the aligned head) and `segment` (against the head it cuts) refuse a file whose points
/// are off that surface, i.e. picked on the raw scan, on another head or in another frame.
/// (straps and assemble check against the layered skin instead, with a wider margin:
/// meshing::require_landmarks_near_skin.)
#include <map>
#include <string>

#include "pipeline/read_landmarks.h"
#include "pipeline/surface_mesh.h"

namespace pipeline {

/// Every landmark of `landmarks` within `max_mm` of `surface`.
///
/// @param[in] landmarks  as read by pipeline::read_landmarks from `path`
/// @param[in] surface    the head they were picked on [mm], same frame
/// @param[in] path       the landmarks file, for the message
/// @param[in] max_mm     largest allowed distance [mm]; `landmarks` puts its points on the surface,
///                       10 mm leaves room for a point picked by hand on a coarser copy
/// @throws Error(bad_input) "<path>: landmark menton is 15.9 mm from the head surface, expected
///         <= 10 mm (same frame as the aligned head?)" for the first landmark, by name, too far.
/// @param[out] distances_mm  optional: each landmark's distance to the surface [mm], by name
void require_landmarks_on_surface(const std::map<std::string, Landmark>& landmarks, const SurfaceMesh& surface,
                                  const std::string& path, double max_mm = 10.0,
                                  std::map<std::string, double>* distances_mm = nullptr);

}  // namespace pipeline
