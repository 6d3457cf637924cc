#include "data/generator/scanner_artifacts.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "pipeline/error.h"

namespace generator {

namespace {

Vector face_cross(const Triangles& tri, std::size_t f) {
  const auto& t = tri.faces[f];
  return CGAL::cross_product(tri.points[t[1]] - tri.points[t[0]], tri.points[t[2]] - tri.points[t[0]]);
}

Vector unit(const Vector& v) {
  const double l = std::sqrt(v.squared_length());
  return l > 0 ? v / l : Vector(0, 0, 0);
}

/// A uniformly distributed random unit vector (normalised Gaussian triple).
Vector random_direction(Rng& rng) {
  for (;;) {
    const Vector v(rng.normal(), rng.normal(), rng.normal());
    if (v.squared_length() > 1e-12) return unit(v);
  }
}

/// Points along the edges where the surface is not smooth: open borders and edges with a
/// dihedral angle above 60°. Holes placed near these would not be clean disks.
std::vector<Point> rough_edge_points(const Triangles& tri) {
  // (edge's lower vertex, higher vertex, face), sorted: each edge's faces in a run, edges in
  // vertex order and faces in index order (a map of vectors gave the same order, ~4x slower).
  std::vector<std::array<std::size_t, 3>> edge_face;
  edge_face.reserve(3 * tri.faces.size());
  for (std::size_t f = 0; f < tri.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      std::size_t a = tri.faces[f][k], b = tri.faces[f][(k + 1) % 3];
      edge_face.push_back({std::min(a, b), std::max(a, b), f});
    }
  std::sort(edge_face.begin(), edge_face.end());
  const double cos60 = 0.5;
  std::vector<Point> out;
  for (std::size_t begin = 0, end = 0; begin < edge_face.size(); begin = end) {
    while (end < edge_face.size() && edge_face[end][0] == edge_face[begin][0] &&
           edge_face[end][1] == edge_face[begin][1])
      ++end;
    bool rough = end - begin != 2;
    if (!rough) rough = unit(face_cross(tri, edge_face[begin][2])) * unit(face_cross(tri, edge_face[begin + 1][2])) < cos60;
    if (!rough) continue;
    // Points every ≤ 2 mm along the edge (long edges, e.g. of a capped neck, matter too).
    const Point& p = tri.points[edge_face[begin][0]];
    const Vector v = tri.points[edge_face[begin][1]] - p;
    const int n = 1 + int(std::sqrt(v.squared_length()) / 2.0);
    for (int k = 0; k <= n; ++k) out.push_back(p + (double(k) / n) * v);
  }
  return out;
}

}  // namespace

Triangles triangles_of(const pipeline::PolygonSoup& soup) {
  Triangles t;
  t.points = soup.points;
  for (std::size_t p = 0; p < soup.polygons.size(); ++p) {
    const auto& poly = soup.polygons[p];
    for (std::size_t i : poly)
      if (i >= soup.points.size())
        throw pipeline::bad_input("polygon " + std::to_string(p),
                                  "vertex index " + std::to_string(i) + " out of range");
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) t.faces.push_back({poly[0], poly[k], poly[k + 1]});
  }
  if (surface_area(t) <= 0) throw pipeline::bad_input("surface", "no triangle of non-zero area");
  return t;
}

Triangles triangles_of(const pipeline::SurfaceMesh& mesh) {
  Triangles t;
  std::map<pipeline::VertexIndex, std::size_t> id;
  for (auto v : mesh.vertices()) {
    id[v] = t.points.size();
    t.points.push_back(mesh.point(v));
  }
  for (auto f : mesh.faces()) {
    std::vector<std::size_t> poly;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) poly.push_back(id[v]);
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) t.faces.push_back({poly[0], poly[k], poly[k + 1]});
  }
  return t;
}

pipeline::SurfaceMesh surface_mesh_of(const Triangles& tri) {
  pipeline::SurfaceMesh mesh;
  std::vector<pipeline::VertexIndex> v;
  v.reserve(tri.points.size());
  for (const auto& p : tri.points) v.push_back(mesh.add_vertex(p));
  for (std::size_t f = 0; f < tri.faces.size(); ++f) {
    const auto& t = tri.faces[f];
    if (mesh.add_face(v[t[0]], v[t[1]], v[t[2]]) == pipeline::SurfaceMesh::null_face())
      throw pipeline::algorithm_failed("surface", "triangle " + std::to_string(f) +
                                                      " makes the mesh non-manifold");
  }
  return mesh;
}

double surface_area(const Triangles& tri) {
  double a = 0;
  for (std::size_t f = 0; f < tri.faces.size(); ++f) a += 0.5 * std::sqrt(face_cross(tri, f).squared_length());
  return a;
}

PointCloud sample_surface(const Triangles& tri, std::size_t n, Rng& rng) {
  // Cumulative areas, then inverse-CDF choice of the triangle and the square-root trick for a
  // uniform point inside it (Osada et al. 2002).
  std::vector<double> cum(tri.faces.size());
  double total = 0;
  for (std::size_t f = 0; f < tri.faces.size(); ++f) {
    total += 0.5 * std::sqrt(face_cross(tri, f).squared_length());
    cum[f] = total;
  }
  if (!(total > 0)) throw pipeline::bad_input("surface", "zero area, nothing to sample");
  PointCloud c;
  c.points.reserve(n);
  c.normals.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double u = rng.uniform() * total;
    std::size_t f = std::upper_bound(cum.begin(), cum.end(), u) - cum.begin();
    if (f >= cum.size()) f = cum.size() - 1;
    const auto& t = tri.faces[f];
    const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
    const Point& a = tri.points[t[0]];
    const Point& b = tri.points[t[1]];
    const Point& d = tri.points[t[2]];
    c.points.push_back(a + r1 * (1 - r2) * (b - a) + r1 * r2 * (d - a));
    c.normals.push_back(unit(face_cross(tri, f)));
  }
  return c;
}

void add_noise(PointCloud& cloud, double sigma_mm, NoiseDirection direction, Rng& rng) {
  if (direction == NoiseDirection::normal && cloud.normals.size() != cloud.points.size())
    throw pipeline::algorithm_failed("add_noise", "noise along the normal needs one normal per point");
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    if (direction == NoiseDirection::normal)
      cloud.points[i] = cloud.points[i] + sigma_mm * rng.normal() * cloud.normals[i];
    else {
      const double dx = rng.normal(), dy = rng.normal(), dz = rng.normal();
      cloud.points[i] = cloud.points[i] + sigma_mm * Vector(dx, dy, dz);
    }
  }
}

std::size_t punch_holes(PointCloud& cloud, const std::vector<Hole>& holes) {
  if (cloud.normals.size() != cloud.points.size())
    throw pipeline::algorithm_failed("punch_holes", "needs one normal per point");
  std::size_t kept = 0;
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    bool inside = false;
    for (const Hole& h : holes)
      if (CGAL::squared_distance(cloud.points[i], h.centre) < h.radius_mm * h.radius_mm &&
          cloud.normals[i] * h.normal > 0) {
        inside = true;
        break;
      }
    if (inside) continue;
    cloud.points[kept] = cloud.points[i];
    cloud.normals[kept] = cloud.normals[i];
    ++kept;
  }
  const std::size_t removed = cloud.points.size() - kept;
  cloud.points.resize(kept);
  cloud.normals.resize(kept);
  return removed;
}

std::vector<Hole> random_holes(const PointCloud& cloud, const Triangles& tri, int count,
                               double diameter_min_mm, double diameter_max_mm, Rng& rng) {
  std::vector<Hole> holes;
  if (count <= 0) return holes;
  if (cloud.points.empty() || cloud.normals.size() != cloud.points.size())
    throw pipeline::algorithm_failed("random_holes", "needs a sampled cloud with normals");
  const std::vector<Point> rough = rough_edge_points(tri);
  const int max_tries = 10000;
  for (int tries = 0; int(holes.size()) < count; ++tries) {
    if (tries > max_tries)
      throw pipeline::algorithm_failed("random_holes", "no room for " + std::to_string(count) +
                                                           " holes away from sharp edges");
    const std::size_t i = rng.index(cloud.points.size());
    const double r = 0.5 * rng.uniform(diameter_min_mm, diameter_max_mm);
    const Point& c = cloud.points[i];
    const double keep = (r + 3.0) * (r + 3.0);
    bool ok = std::none_of(rough.begin(), rough.end(),
                           [&](const Point& q) { return CGAL::squared_distance(c, q) < keep; });
    for (const Hole& h : holes)
      ok = ok && std::sqrt(CGAL::squared_distance(c, h.centre)) > r + h.radius_mm + 5.0;
    if (ok) holes.push_back({c, cloud.normals[i], r});
  }
  return holes;
}

std::size_t add_outliers(PointCloud& cloud, const OutlierOptions& opt, Rng& rng) {
  if (!(opt.fraction >= 0 && opt.fraction < 0.5))
    throw pipeline::Error(pipeline::ErrorKind::usage,
                          "outlier fraction " + pipeline::format_number(opt.fraction) + " out of range [0, 0.5)");
  const std::size_t n = cloud.points.size();
  if (n == 0 || opt.fraction == 0) return 0;
  const bool normals = cloud.normals.size() == n;
  const auto added = std::size_t(std::llround(opt.fraction * double(n) / (1.0 - opt.fraction)));
  for (std::size_t k = 0; k < added; ++k) {
    const std::size_t i = rng.index(n);
    const Vector nrm = normals ? cloud.normals[i] : random_direction(rng);
    Point p;
    if (rng.uniform() < opt.spike_share) {
      const double d = rng.uniform(opt.spike_min_mm, opt.spike_max_mm);
      p = cloud.points[i] + (rng.uniform() < 0.5 ? d : -d) * nrm;
    } else {
      const double d = rng.uniform(opt.outlier_min_mm, opt.outlier_max_mm);
      p = cloud.points[i] + d * random_direction(rng);
    }
    cloud.points.push_back(p);
    if (normals) cloud.normals.push_back(nrm);
  }
  return added;
}

PointCloud scan_surface(const Triangles& tri, const ScanOptions& opt, Rng& rng,
                        std::vector<Hole>* holes_used) {
  PointCloud cloud = sample_surface(tri, opt.points, rng);
  std::vector<Hole> holes = opt.holes;
  const auto random = random_holes(cloud, tri, opt.random_holes, opt.hole_diameter_min_mm,
                                   opt.hole_diameter_max_mm, rng);
  holes.insert(holes.end(), random.begin(), random.end());
  punch_holes(cloud, holes);
  // Outliers start from clean positions, then everything gets the same scanner noise.
  add_outliers(cloud, opt.outliers, rng);
  add_noise(cloud, opt.noise_mm, opt.noise_direction, rng);
  cloud.normals.clear();
  if (holes_used) *holes_used = holes;
  return cloud;
}

}  // namespace generator
