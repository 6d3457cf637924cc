#pragma once
// Small meshes with known geometry for the scan2cad tests.
#include <algorithm>
#include <cmath>
#include <vector>

#include "pipeline/surface_mesh.h"

namespace test_meshes {

/// A UV sphere of radius r [mm] centred at the origin, closed and outward-oriented.
/// `rings` latitude bands, 2·rings longitude segments (edge ≈ π r / rings).
inline pipeline::PolygonSoup sphere_soup(double r, int rings) {
  pipeline::PolygonSoup s;
  const int segs = 2 * rings;
  const double pi = std::acos(-1.0);
  s.points.emplace_back(0, 0, r);  // north pole 0
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segs; ++j) {
      const double th = pi * i / rings, ph = 2 * pi * j / segs;
      s.points.emplace_back(r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th));
    }
  const std::size_t south = s.points.size();
  s.points.emplace_back(0, 0, -r);
  auto id = [&](int i, int j) { return std::size_t(1 + (i - 1) * segs + (j % segs)); };
  for (int j = 0; j < segs; ++j) s.polygons.push_back({0, id(1, j), id(1, j + 1)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segs; ++j) {
      s.polygons.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.polygons.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  for (int j = 0; j < segs; ++j) s.polygons.push_back({south, id(rings - 1, j + 1), id(rings - 1, j)});
  return s;
}

/// The front half (z > 0) of sphere_soup(r, rings): an open cup, a respirator-like shell with one
/// rim.
inline pipeline::PolygonSoup cup_soup(double r, int rings) {
  pipeline::PolygonSoup s = sphere_soup(r, rings);
  std::vector<std::vector<std::size_t>> keep;
  for (const auto& f : s.polygons)
    if (s.points[f[0]].z() > 0 && s.points[f[1]].z() > 0 && s.points[f[2]].z() > 0) keep.push_back(f);
  s.polygons = keep;
  return s;
}

/// Largest |distance to the origin − r| over the vertices of `m` [mm]: the error of a mesh
/// meant to be the sphere of radius r centred at the origin.
inline double max_radial_error(const pipeline::SurfaceMesh& m, double r) {
  double worst = 0;
  for (auto v : m.vertices())
    worst = std::max(worst, std::abs(std::sqrt((m.point(v) - CGAL::ORIGIN).squared_length()) - r));
  return worst;
}

/// The soup as a Surface_mesh.
inline pipeline::SurfaceMesh mesh_of(const pipeline::PolygonSoup& s) {
  pipeline::SurfaceMesh m;
  std::vector<pipeline::VertexIndex> v;
  for (const auto& p : s.points) v.push_back(m.add_vertex(p));
  for (const auto& f : s.polygons) m.add_face(v[f[0]], v[f[1]], v[f[2]]);
  return m;
}

}  // namespace test_meshes
