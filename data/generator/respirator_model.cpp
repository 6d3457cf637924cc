#include "data/generator/respirator_model.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "pipeline/error.h"
#include "pipeline/read_json.h"

namespace generator {

RespiratorParams read_respirator_params(const std::string& path, const std::string& id, HeadParams* face) {
  const nlohmann::json j = pipeline::read_json(path);
  if (!j.contains("respirators") || !j["respirators"].is_object())
    throw pipeline::bad_input(path, "no \"respirators\" object");
  if (!j["respirators"].contains(id)) {
    std::string known;
    for (auto it = j["respirators"].begin(); it != j["respirators"].end(); ++it) known += " " + it.key();
    throw pipeline::bad_input(path, "unknown respirator id '" + id + "', known:" + known);
  }
  const auto& r = j["respirators"][id];
  // wall, clearance and nose_drop have defaults: a misspelt one ("wal": 2) was read as absent
  if (const std::string key =
          pipeline::first_unknown_key(r, {"width", "height", "depth", "wall", "clearance", "nose_drop"});
      !key.empty())
    throw pipeline::bad_input(path, "respirator '" + id + "': unknown key \"" + key + "\"");
  RespiratorParams p;
  struct F { const char* name; double* v; double lo, hi; bool required; };
  for (const F& f : {F{"width", &p.width, 80, 180, true}, F{"height", &p.height, 80, 170, true},
                     F{"depth", &p.depth, 20, 90, true}, F{"wall", &p.wall, 0.5, 4, false},
                     F{"clearance", &p.clearance, 2, 30, false}, F{"nose_drop", &p.nose_drop, -10, 30, false}}) {
    if (!r.contains(f.name)) {
      if (f.required) throw pipeline::bad_input(path, "respirator '" + id + "': missing \"" + f.name + "\"");
      continue;
    }
    if (!r[f.name].is_number() || !(r[f.name].get<double>() >= f.lo && r[f.name].get<double>() <= f.hi))
      throw pipeline::bad_input(path, "respirator '" + id + "': \"" + f.name + "\" must be a number in [" +
                                          pipeline::format_number(f.lo) + ", " + pipeline::format_number(f.hi) + "] mm");
    *f.v = r[f.name].get<double>();
  }
  *face = head_params_from_json(j, path, "average");  // the face the cups sit on, in the same file
  return p;
}

Triangles make_respirator(const RespiratorParams& p, const HeadShape& face, RimSize* rim) {
  const HeadDimensions d = measure_head(face.mesh(6), "average face");
  const double y_top = d.sellion.y() - p.nose_drop;
  const double y_bot = std::max(y_top - p.height, d.menton.y() + 2.0);  // stays on the chin front
  const double yc = 0.5 * (y_top + y_bot), b = 0.5 * (y_top - y_bot), a = 0.5 * p.width;
  const int N = 40, M = 192;  // rings, angles
  auto outline = [&](double rho, double th) {
    // Egg: narrower over the nose (θ = 0 at the top), full width at the cheeks and chin.
    const double w = 0.72 + 0.28 * std::sqrt(0.5 * (1 - std::cos(th)));
    return std::make_pair(rho * a * w * std::sin(th), yc + rho * b * std::cos(th));
  };
  auto face_z = [&](double x, double y) {
    Point h;
    if (!face.front_hit(x, y, &h))
      throw pipeline::algorithm_failed("respirator", "point (" + pipeline::format_number(x) + ", " +
                                                         pipeline::format_number(y) + ") misses the face");
    return h.z();
  };
  const double pi = 3.14159265358979323846;
  // Each rim point goes as far out along its angle as the face allows: it must land on the
  // front of the face (normal facing +z by at least 0.35), so a rim wider than the face
  // follows the cheek instead of falling off it.
  std::vector<double> reach(M, 1.0), z_rim(M);
  for (int j = 0; j < M; ++j) {
    const double th = 2 * pi * j / M;
    for (double r = 1.0; r > 0.3; r -= 0.01) {
      const auto [x, y] = outline(r, th);
      Point h;
      if (face.front_hit(x, y, &h) && face.normal(h).z() >= 0.35 && h.z() >= d.pronasale.z() - 60) {
        reach[j] = r;
        z_rim[j] = h.z();
        break;
      }
      if (r - 0.01 <= 0.3) throw pipeline::algorithm_failed("respirator", "rim cannot be placed on the face");
    }
  }
  // Smooth the reach over angles (moving average of the minimum over ±6 angles) so the rim
  // has no notches; a smaller reach always stays on the face.
  {
    std::vector<double> lo(M), sm(M);
    for (int j = 0; j < M; ++j) {
      lo[j] = 1.0;
      for (int k = -6; k <= 6; ++k) lo[j] = std::min(lo[j], reach[(j + k + M) % M]);
    }
    for (int j = 0; j < M; ++j) {
      sm[j] = 0;
      for (int k = -6; k <= 6; ++k) sm[j] += lo[(j + k + M) % M] / 13.0;
    }
    reach = sm;
  }
  // Symmetry about x = 0: angle j mirrors to M − j.
  for (int j = 0; j <= M / 2; ++j) {
    const double r = std::min(reach[j], reach[(M - j) % M]);
    reach[j] = reach[(M - j) % M] = r;
    const auto [x, y] = outline(r, 2 * pi * j / M);
    z_rim[j] = z_rim[(M - j) % M] = face_z(std::abs(x), y);
  }
  auto grid = [&](int i, int j) { return outline(double(i) / N * reach[(j + M) % M], 2 * pi * j / M); };
  if (rim) {
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (int j = 0; j < M; ++j) {
      const auto [x, y] = grid(N, j);
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
    *rim = {x1 - x0, y1 - y0};
  }
  // Interior base height: rim heights blended toward their mean at the centre.
  double z_mean = 0;
  for (double z : z_rim) z_mean += z / M;
  auto base = [&](int i, int j) { const double r = double(i) / N; return r * r * z_rim[j] + (1 - r * r) * z_mean; };
  auto bulge = [&](int i) { const double r = double(i) / N; return std::pow(1 - r * r, 0.7); };
  double D = p.depth;
  for (int i = 0; i <= int(0.8 * N); ++i)  // the rim band follows the face by construction
    for (int j = 0; j < M; ++j) {
      const auto [x, y] = grid(i, j);
      D = std::max(D, (face_z(x, y) + p.clearance * (1 - double(i) / N) - base(i, j)) / bulge(i));
      if (i == 0) break;  // the centre is one point
    }
  Triangles t;
  auto add = [&](int i, int j, double dz) {
    const auto [x, y] = grid(i, j);
    t.points.emplace_back(x, y, base(i, j) + D * bulge(i) + dz);
    return t.points.size() - 1;
  };
  // Vertex layout per sheet: centre, then rings 1..N of M points.
  const std::size_t in0 = add(0, 0, 0);
  for (int i = 1; i <= N; ++i) for (int j = 0; j < M; ++j) add(i, j, 0);
  auto v = [&](std::size_t s0, int i, int j) { return i == 0 ? s0 : s0 + 1 + std::size_t(i - 1) * M + std::size_t((j + M) % M); };
  // The outer sheet is the inner one moved by `wall` along its normal (away from the face), so
  // the wall is `wall` thick everywhere like a real shell: moved along z instead, it thinned to
  // wall·|n_z| (~0.3 mm) on the steep band by the rim, where a scan's two sides then merge
  // within the noise. Normals: area-weighted normals of the inner triangles (they face −z).
  std::vector<Vector> normal(t.points.size(), Vector(0, 0, 0));
  auto accumulate = [&](std::size_t a, std::size_t b, std::size_t c) {
    const Vector n = CGAL::cross_product(t.points[b] - t.points[a], t.points[c] - t.points[a]);
    normal[a] = normal[a] + n, normal[b] = normal[b] + n, normal[c] = normal[c] + n;
  };
  for (int j = 0; j < M; ++j) accumulate(v(in0, 0, 0), v(in0, 1, j), v(in0, 1, j + 1));
  for (int i = 1; i < N; ++i)
    for (int j = 0; j < M; ++j) {
      accumulate(v(in0, i, j), v(in0, i + 1, j), v(in0, i + 1, j + 1));
      accumulate(v(in0, i, j), v(in0, i + 1, j + 1), v(in0, i, j + 1));
    }
  // The polar grid's diagonals all lean one way; mirror-averaging keeps the shell symmetric.
  auto mirrored = [](const Vector& n) { return Vector(-n.x(), n.y(), n.z()); };
  normal[v(in0, 0, 0)] = Vector(0, normal[v(in0, 0, 0)].y(), normal[v(in0, 0, 0)].z());
  for (int i = 1; i <= N; ++i)
    for (int j = 0; j <= M / 2; ++j) {
      const Vector sum = normal[v(in0, i, j)] + mirrored(normal[v(in0, i, M - j)]);
      normal[v(in0, i, j)] = sum;
      normal[v(in0, i, M - j)] = mirrored(sum);
    }
  const std::size_t out0 = t.points.size();
  for (std::size_t k = in0; k < out0; ++k)
    t.points.push_back(t.points[k] - p.wall / std::sqrt(normal[k].squared_length()) * normal[k]);
  // θ runs clockwise seen from +z, so (centre, j, j+1) faces −z: the inner sheet faces the face.
  for (int j = 0; j < M; ++j) {
    t.faces.push_back({v(in0, 0, 0), v(in0, 1, j), v(in0, 1, j + 1)});
    t.faces.push_back({v(out0, 0, 0), v(out0, 1, j + 1), v(out0, 1, j)});
  }
  for (int i = 1; i < N; ++i)
    for (int j = 0; j < M; ++j) {
      t.faces.push_back({v(in0, i, j), v(in0, i + 1, j), v(in0, i + 1, j + 1)});
      t.faces.push_back({v(in0, i, j), v(in0, i + 1, j + 1), v(in0, i, j + 1)});
      t.faces.push_back({v(out0, i, j), v(out0, i + 1, j + 1), v(out0, i + 1, j)});
      t.faces.push_back({v(out0, i, j), v(out0, i, j + 1), v(out0, i + 1, j + 1)});
    }
  for (int j = 0; j < M; ++j) {  // rim strip, facing outward
    t.faces.push_back({v(in0, N, j), v(out0, N, j), v(out0, N, j + 1)});
    t.faces.push_back({v(in0, N, j), v(out0, N, j + 1), v(in0, N, j + 1)});
  }
  return t;
}

}  // namespace generator
