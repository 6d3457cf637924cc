#pragma once
/// Reading scans and meshes. Scanner formats: PLY (ascii/binary), STL (ascii/binary), OBJ, OFF
/// (meshes or point sets) and points as text, .xyz .pts .txt .csv .asc (x y z, then any columns:
/// the normals are the three that are unit vectors, the others are left out with a note; see
/// read_xyz in read_scan.cpp for separators, headers and Leica PTS). PLY and OFF are read with
/// CGAL, points as text by read_xyz (written here), STL and OBJ meshes with assimp (an OBJ of
/// vertices only by read_obj_points). PLY face indices of 8 or 16 bits, which CGAL's reader
/// does not take, are widened to 32 bits in memory first.
#include <string>
#include <vector>

#include "pipeline/surface_mesh.h"
#include "pipeline/units.h"

namespace pipeline {

struct ScanReadOptions {
  Unit unit = Unit::automatic;     ///< unit of the file; automatic guesses from the size
  double expected_size_mm = head_extent_mm; ///< real largest extent of the object (units.h)
};

/// A scan as read: either a polygon soup (is_mesh) or a point cloud, already scaled to mm.
struct Scan {
  bool is_mesh = false;
  PolygonSoup soup;    ///< filled when is_mesh
  PointCloud cloud;    ///< filled otherwise
  Unit unit = Unit::mm;  ///< unit the file was in (detected or forced)
  /// largest extent without a few far points [mm] (extent_without_far_points): the size the unit
  /// was judged by, which the stages log and check a forced unit against
  double extent_mm = 0;
  /// What the reader left out of the file, for the stage's log ("columns 4-6 are colours ...")
  std::vector<std::string> notes;
};

/// Reads a scan file of any supported format and scales it to mm.
///
/// @param[in] path  file to read; the format is chosen by extension and checked by content
/// @param[in] opt   unit handling
/// @return the scan in mm
/// @throws Error(bad_input) naming `path` if the file is missing, empty, truncated, not of its
///         format, holds more than its PLY or OFF header declares (a lowered count was read as
///         fewer points or faces), has non-finite coordinates, no points, or a size no unit
///         explains.
Scan read_scan(const std::string& path, const ScanReadOptions& opt = {});

/// Reads a triangle mesh that a previous stage wrote (mm, no unit guessing) into a Surface_mesh,
/// keeping PLY vertex/face properties (e.g. "f:part").
/// @throws Error(bad_input) if unreadable, empty, non-finite, not a 2-manifold polygon mesh, with
///         a face of more than 3 corners, or with a degenerate (zero-area) triangle.
SurfaceMesh read_surface_mesh(const std::string& path);

}  // namespace pipeline
