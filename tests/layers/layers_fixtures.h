#pragma once
/// Test fixtures shared by the layers, straps and assemble tests: a labelled surface of a real NIOSH
/// headform (CGAL isotropic remeshing + crude box labels, like segment's parts), crude landmarks of
/// it, and a parabolic dome standing in for a respirator's inner face. Test data only.
#include <nlohmann/json.hpp>
#include <string>

#include "layering/layers.h"

namespace fixtures {

/// NIOSH STL (y up, face toward +z) remeshed to `edge_mm`, triangles labelled forehead (incl. the
/// nose), left_cheek (x > 0), right_cheek, chin, back_of_head by boxes around the face.
layering::FeModel niosh_surface(const std::string& stl, double edge_mm);
/// Landmarks JSON (landmarks format) found on the same surface by simple extreme-point rules.
nlohmann::json niosh_landmarks(const layering::FeModel& head);
/// Parabolic cup z = depth·(1 − (x/a)² − (y/b)²) over an ellipse, meshed by gmsh, one triangle
/// group respirator_inner (normals toward −z). [mm]
layering::FeModel dome_respirator(double a = 60, double b = 66, double depth = 42, double size = 4);

}  // namespace fixtures
