#pragma once
/// Smooth-surface (CAD) step of the paper, done with gmsh: each labelled part of a segmented
/// surface becomes a discrete gmsh surface with its boundary curves (shared between neighbouring
/// parts), and gmsh computes a parametrization of each part (model::mesh::createGeometry), so
/// that the geometry can be re-meshed at any size. This needs disk-like parts: whole closed heads
/// fail ("Wrong topology of boundary mesh for parametrization"), which is why `segment` comes
/// first. The parametrized surface passes through the input triangles (it interpolates them), so
/// the fitted geometry deviates from the repaired mesh only by what re-meshing moves.
#include <string>
#include <vector>

#include "pipeline/surface_mesh.h"

namespace scan2cad {

/// One part as a gmsh surface.
struct FitPart {
  std::string name;     ///< physical group name (forehead, ..., or respirator_inner)
  int label = 0;        ///< "f:part" value
  int surface_tag = 0;  ///< gmsh surface tag (= physical group tag)
};

/// Builds the parametrized, part-wise geometry in the CURRENT gmsh model (gmsh must be
/// initialized; the model is cleared first): one discrete surface and one named 2D physical
/// group per part, boundary curves shared, parametrizations computed.
///
/// @param[in] segmented  triangle mesh [mm] with int face property "f:part"
/// @param[in] kind       "head" (labels 0..4: back_of_head, forehead, left_cheek, right_cheek,
///                       chin) or "respirator" (one part, label 0, named respirator_inner)
/// @return the parts, in label order
/// @throws pipeline::Error(bad_input) if "f:part" is missing or a label is unknown for `kind`;
///         Error(algorithm) if gmsh cannot parametrize a part (not a disk)
std::vector<FitPart> fit_surfaces(const pipeline::SurfaceMesh& segmented, const std::string& kind);

/// Deviation of the fitted geometry from the reference (repaired) mesh, per part.
struct FitDeviation {
  std::string name;
  std::size_t samples = 0;   ///< nodes of the check mesh on this part
  double rms_mm = 0, max_mm = 0;              ///< distance of points ON the fitted surface [mm]
  double chord_rms_mm = 0, chord_max_mm = 0;  ///< distance of the check triangles' centroids [mm]
};

/// Meshes the current (fitted) gmsh model at `check_size_mm` and measures, per part, the
/// distance of the new nodes (points of the fitted surface) and of the triangle centroids
/// (chord error of a mesh of that size) to `reference`. Replaces the model's mesh: call it after
/// the fitted geometry has been written.
/// @throws pipeline::Error(algorithm) if gmsh cannot mesh a part
std::vector<FitDeviation> fit_deviation(const pipeline::SurfaceMesh& reference,
                                        const std::vector<FitPart>& parts, double check_size_mm);

}  // namespace scan2cad
