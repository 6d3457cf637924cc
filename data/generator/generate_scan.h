#pragma once
/// The library call behind the generate_scan program: builds (or reads) a clean surface and
/// simulates a structured-light scan of it (see scanner_artifacts.h).
#include <cstdint>
#include <string>
#include <vector>

#include "data/generator/scanner_artifacts.h"
#include "pipeline/surface_mesh.h"

namespace generator {

/// The widest mean point spacing a scan may have [mm]: a head of ~1,200 points. Bounds
/// --spacing-mm and the spacing --points gives.
constexpr double max_scan_spacing_mm = 10.0;

/// What to scan and how. Either mesh_path (scan a given mesh) or kind + id + params_path
/// (a generated headform or respirator) must be set, not both.
struct GenerateRequest {
  std::string kind;         ///< "head" or "respirator": the generated model, or what --from-mesh is (its size)
  std::string id;           ///< model id in the params file ("medium", "onesize", ...)
  std::string params_path;  ///< headforms.json or respirators.json
  std::string mesh_path;    ///< a mesh to scan (PLY/STL/OBJ/OFF, any unit read_scan detects)
  std::string unit = "auto";///< the mesh's length unit: auto, mm, cm, m or in (pipeline::parse_unit)
  int points = 0;           ///< samples before holes/outliers; 0: area / spacing_mm²
  double spacing_mm = 0.6;  ///< mean spacing of a structured-light scanner [mm], [0.1, max_scan_spacing_mm]
  double noise_mm = 0.2;    ///< Gaussian noise σ [mm]
  NoiseDirection noise_direction = NoiseDirection::normal;
  double outlier_fraction = 0.005;  ///< outliers + spikes share of the output, [0, 0.5)
  int random_holes = -1;    ///< random holes; -1: 0 for a given mesh, 1 for generated models
  double hole_diameter_min_mm = 10.0, hole_diameter_max_mm = 20.0;
  bool no_model_holes = false;  ///< generated models: skip the chin/ear holes
  std::uint64_t seed = 1;
  bool want_clean_mesh = true;  ///< also return the clean surface as a Surface_mesh
};

struct GeneratedScan {
  pipeline::PointCloud cloud;      ///< the simulated scan [mm], no normals
  pipeline::SurfaceMesh clean_mesh;///< the surface that was scanned (if requested)
  std::vector<Hole> holes;         ///< every hole made
  /// For a generated respirator: what the rim's size came to against the design, e.g. "rim
  /// 111.1 x 106.9 mm as built (design 128 x 118: ...)"; empty otherwise.
  std::string rim_note;
  /// For --from-mesh: the unit the mesh was read in and the size that gives (pipeline::describe_unit).
  std::string unit_note;
};

/// Builds the surface and scans it. Same request → same cloud, bit for bit.
/// @throws Error(usage) on inconsistent options, Error(bad_input) on an unreadable mesh or
///         params file or an unknown id, Error(algorithm) if the model cannot be built.
GeneratedScan generate_scan(const GenerateRequest& rq);

/// Parses "MIN:MAX" (or one number) hole diameters [mm], 0 < MIN <= MAX <= 100. @throws Error(usage).
void parse_hole_diameters(const std::string& text, double* min_mm, double* max_mm);
/// "normal" or "isotropic". @throws Error(usage).
NoiseDirection parse_noise_direction(const std::string& text);
/// Writes {"holes": [{"centre": [x,y,z], "normal": [..], "radius_mm": r}, ...]} atomically.
void write_holes_json(const std::string& path, const std::vector<Hole>& holes);

}  // namespace generator
