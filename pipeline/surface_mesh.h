#pragma once
/// The geometric types every geometry stage shares: CGAL's Surface_mesh half-edge structure and
/// a point cloud with optional normals. Coordinates are in mm.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <array>
#include <vector>

namespace pipeline {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using VertexIndex = SurfaceMesh::Vertex_index;
using FaceIndex = SurfaceMesh::Face_index;

/// A scanned point cloud [mm]. `normals` is empty or has one unit normal per point.
struct PointCloud {
  std::vector<Point> points;
  std::vector<Vector> normals;
};

/// An indexed triangle/polygon soup as read from a file, before it is made a manifold mesh.
struct PolygonSoup {
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
};

/// Name of the per-face part label property on segmented meshes ("f:part", int).
inline constexpr const char* part_property = "f:part";

}  // namespace pipeline
