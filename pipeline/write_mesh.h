#pragma once
/// Writing meshes and point clouds, atomically (temporary file + rename). The format follows the
/// extension: .ply (binary, keeps vertex/face properties), .off, .obj, .stl; points: .ply, .xyz.
#include <string>
#include <vector>

#include "pipeline/surface_mesh.h"

namespace pipeline {

/// The endings write_surface_mesh and write_point_cloud write, for require_extension (cli.h).
inline const std::vector<std::string> surface_mesh_extensions = {".ply", ".off", ".obj", ".stl"};
inline const std::vector<std::string> point_cloud_extensions = {".ply", ".xyz"};

/// @throws Error(io) when writing fails; `path` is then untouched.
void write_surface_mesh(const std::string& path, const SurfaceMesh& mesh);

/// Writes a polygon soup as it is (faces of any size, no orientation or manifold check).
/// @throws Error(io) when writing fails; `path` is then untouched.
void write_polygon_soup(const std::string& path, const PolygonSoup& soup);

/// Writes points (and normals when present). @throws Error(io) when writing fails.
void write_point_cloud(const std::string& path, const PointCloud& cloud);

}  // namespace pipeline
