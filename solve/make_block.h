#pragma once
/// Small models built in memory, for tests and benchmarks (no .msh needed): structured blocks of
/// solids and flat plates of membranes, optionally with jittered interior nodes (irregular
/// meshes), plus a merge of two models into one (two bodies for contact tests).
///
/// Named groups created: node groups "xmin" "xmax" "ymin" "ymax" "zmin" "zmax" (faces of the
/// block / edges of the plate), "all" (every node) and the part name (default "block" /
/// "plate"); for solids the six faces also get outward surface triangles of their name (the
/// part and "all" get none, unlike a part read from a .msh).
/// The returned model has one material (`mat`) and one part; control.end_time = 1 ms; everything
/// else at its default, ready for the caller to add constraints, loads and contact.
#include <array>
#include <string>

#include "solve/model.h"

namespace solve {

struct BlockSpec {
  ElementType type = ElementType::hex8;        ///< hex8, wedge6 (2 per cell) or tet4 (6 per cell)
  int nx = 2, ny = 2, nz = 2;                  ///< cells per direction, ≥ 1
  std::array<double, 3> size{1, 1, 1};         ///< [mm]
  std::array<double, 3> origin{0, 0, 0};       ///< [mm]
  double jitter = 0;   ///< interior nodes moved by up to jitter × cell size per axis, [0, 0.3]
  unsigned seed = 1;   ///< of the jitter
  std::string part = "block";
};

/// Structured block of solids. @throws pipeline::Error(bad_input) on a bad spec.
Model make_block(const BlockSpec& spec, const Material& mat);

struct PlateSpec {
  ElementType type = ElementType::quad4;  ///< quad4 or tri3 (2 per cell)
  int nx = 2, ny = 2;
  std::array<double, 2> size{1, 1};       ///< [mm], in the plane z = origin z
  std::array<double, 3> origin{0, 0, 0};
  double thickness = 1;                   ///< [mm]
  double jitter = 0;
  unsigned seed = 1;
  std::string part = "plate";
};

/// Flat membrane plate in the xy plane.
Model make_plate(const PlateSpec& spec, const Material& mat);

/// Appends src to dst: nodes, parts, materials (renamed prefix + name), node groups and surfaces
/// (renamed prefix + name), constraints, loads, initial velocities, ties and contacts (group
/// names prefixed). dst keeps its control and output settings.
void append_model(Model& dst, const Model& src, const std::string& prefix);

}  // namespace solve
