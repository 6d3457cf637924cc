#pragma once
/// Scanner artifacts: turn a clean triangle surface into a point cloud that looks like the
/// output of a structured-light scanner (area-uniform samples, Gaussian noise, holes where the
/// scanner saw nothing, outliers and spikes). Every function is deterministic given its Rng.
///
/// Typical use (what `generate_scan --from-mesh` does):
///   generator::Rng rng(seed);
///   auto cloud = generator::sample_surface(mesh, 200000, rng);          // points + normals
///   auto holes = generator::random_holes(cloud, mesh, 3, 10, 20, rng);  // diameters [mm]
///   generator::punch_holes(cloud, holes);
///   generator::add_noise(cloud, 0.3, generator::NoiseDirection::normal, rng);
///   generator::add_outliers(cloud, {0.01}, rng);
///   cloud.normals.clear();                                             // scanners give none
#include <array>
#include <cstddef>
#include <vector>

#include "data/generator/random.h"
#include "pipeline/surface_mesh.h"

namespace generator {

using pipeline::Point;
using pipeline::PointCloud;
using pipeline::Vector;

/// An indexed triangle surface [mm]: #P points, #F×3 indices into points.
struct Triangles {
  std::vector<Point> points;
  std::vector<std::array<std::size_t, 3>> faces;
};

/// Triangles of a polygon soup (polygons are fan-triangulated). @throws Error(bad_input) on an
/// index out of range or when no triangle of non-zero area remains.
Triangles triangles_of(const pipeline::PolygonSoup& soup);
/// Triangles of a surface mesh (faces fan-triangulated).
Triangles triangles_of(const pipeline::SurfaceMesh& mesh);
/// The surface mesh of a triangle list (must be a 2-manifold; used for the clean reference mesh).
pipeline::SurfaceMesh surface_mesh_of(const Triangles& tri);

/// Total area of the triangles [mm²].
double surface_area(const Triangles& tri);

/// `n` points uniformly distributed by area on the triangles, each with the unit normal of its
/// triangle (orientation as given by the vertex order). Deterministic for a given rng state.
/// @throws Error(bad_input) if the surface has zero area.
PointCloud sample_surface(const Triangles& tri, std::size_t n, Rng& rng);

enum class NoiseDirection {
  normal,    ///< displacement along the point's normal (needs cloud.normals)
  isotropic  ///< independent N(0, σ²) on x, y and z
};

/// Adds zero-mean Gaussian noise of standard deviation `sigma_mm` [mm] to every point.
/// @pre for NoiseDirection::normal, cloud.normals has one unit normal per point (checked).
void add_noise(PointCloud& cloud, double sigma_mm, NoiseDirection direction, Rng& rng);

/// A region the scanner did not see: the points within `radius_mm` of `centre` whose normal
/// faces the same way as `normal` (n·normal > 0) are missing. The normal test keeps the
/// opposite side of thin parts (ears, the respirator shell) intact.
struct Hole {
  Point centre;
  Vector normal;
  double radius_mm;
};

/// Removes the points inside the holes. Returns the number of points removed.
/// @pre cloud.normals has one normal per point (checked).
std::size_t punch_holes(PointCloud& cloud, const std::vector<Hole>& holes);

/// Chooses `count` hole centres at random cloud points, with diameters uniform in
/// [diameter_min_mm, diameter_max_mm]. Centres keep (radius + 3 mm) away from sharp edges
/// (dihedral angle > 60°) and open borders of `tri` and the holes do not overlap, so each hole
/// is a clean disk on a smooth part of the surface. @throws Error(algorithm) if no such place
/// is found after many tries (surface too small for the holes).
std::vector<Hole> random_holes(const PointCloud& cloud, const Triangles& tri, int count,
                               double diameter_min_mm, double diameter_max_mm, Rng& rng);

/// Outliers and spikes added to a scan.
struct OutlierOptions {
  double fraction = 0.005;      ///< share of the FINAL cloud that are outliers/spikes, [0, 0.5)
  double spike_share = 0.5;     ///< of those, the share that are spikes (rest: stray outliers)
  double spike_min_mm = 2.0;    ///< spike: a point moved along ±normal by [min, max] mm
  double spike_max_mm = 10.0;
  double outlier_min_mm = 5.0;  ///< stray outlier: a point moved in a random direction by [min, max] mm
  double outlier_max_mm = 40.0;
};

/// Appends round(f·n / (1 − f)) points (n = current size), so that they are the fraction f of
/// the result. Each starts at a random existing point (its clean position, before any noise
/// if called after sampling) and is displaced as described in OutlierOptions; new points get
/// the normal of their origin. Returns the number of points added.
std::size_t add_outliers(PointCloud& cloud, const OutlierOptions& opt, Rng& rng);

/// Everything a simulated scan does, in order: sample, holes, outliers, noise.
struct ScanOptions {
  std::size_t points = 200000;        ///< samples on the surface before holes and outliers
  double noise_mm = 0.2;              ///< Gaussian noise σ [mm]
  NoiseDirection noise_direction = NoiseDirection::normal;
  OutlierOptions outliers;            ///< fraction 0.005 by default
  int random_holes = 0;               ///< number of random holes
  double hole_diameter_min_mm = 10.0;
  double hole_diameter_max_mm = 20.0;
  std::vector<Hole> holes;            ///< holes at given places (e.g. under the chin, in the ears)
};

/// Simulates a scan of `tri`. The returned cloud has no normals. `holes_used`, when given,
/// receives every hole made (given + random).
PointCloud scan_surface(const Triangles& tri, const ScanOptions& opt, Rng& rng,
                        std::vector<Hole>* holes_used = nullptr);

}  // namespace generator
