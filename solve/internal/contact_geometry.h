#pragma once
/// Geometry kernels of the penalty contact (used by solve/contact.cpp and its tests):
/// closest point on a triangle with the feature it lies on, and a uniform-grid bucket sort of
/// axis-aligned boxes for the contact search.
///
/// Written by hand rather than with CGAL's AABB tree because contact needs, per query, the
/// closest *feature* (face, edge or vertex, for the pseudo-normal sign test and the edge/vertex
/// tie-break), the search is re-built thousands of times per run on moving triangles, and the
/// grid build is a deterministic O(n) counting sort that is trivially re-entrant for OpenMP.
#include <array>
#include <cstddef>
#include <vector>

namespace solve::internal {

/// Feature of a triangle a closest point lies on.
enum class Feature : int {
  face = 0,
  edge0 = 1, edge1 = 2, edge2 = 3,  ///< edge k joins corners k and (k+1)%3
  vertex0 = 4, vertex1 = 5, vertex2 = 6
};

struct ClosestPoint {
  std::array<double, 3> point;   ///< closest point [mm]
  std::array<double, 3> weight;  ///< barycentric weights of the corners, sum 1, each in [0, 1]
  Feature feature;
  double dist2;                  ///< squared distance to the query point [mm²]
};

/// Closest point of triangle (a, b, c) to p, with the Voronoi region (feature) it lies in.
/// Follows Ericson, Real-Time Collision Detection §5.1.5; a degenerate triangle is handled by
/// the edge/vertex branches. A point exactly on a region boundary goes to the feature tested first
/// (vertices before edges before the face, in Ericson's order); the closest point is the same
/// either way, so neighbouring facets leave no gap.
ClosestPoint closest_point_on_triangle(const double* p, const double* a, const double* b,
                                       const double* c);

/// Uniform grid of boxes: box i is listed in every cell it overlaps. Cells are cubes of side
/// `cell` from `lo`; `start` (#cells+1) indexes `items` (box ids ascending within each cell).
struct BoxGrid {
  std::array<double, 3> lo{0, 0, 0};
  double cell = 1;
  std::array<long, 3> n{0, 0, 0};
  std::vector<int> start, items;

  /// Bucket-sorts boxes (#boxes×6: xmin ymin zmin xmax ymax zmax [mm]) into cubes of side
  /// cell_factor × the mean box size, coarsened so that the cell count stays below
  /// 8·#boxes + 64. O(#boxes / cell_factor³).
  void build(const std::vector<std::array<double, 6>>& boxes, double cell_factor = 1);
  /// Index of the cell containing p, or -1 outside the grid.
  long cell_of(const double* p) const;
  /// Boxes listed in cell `id` (from cell_of; id ≥ 0): [first, last).
  const int* begin(long id) const { return items.data() + start[id]; }
  const int* end(long id) const { return items.data() + start[id + 1]; }
};

}  // namespace solve::internal
