#include "data/generator/measure_head.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "pipeline/error.h"

namespace generator {

namespace {

/// Points where mesh edges cross the plane x = 0.
std::vector<Point> sagittal_profile(const Triangles& t) {
  std::vector<Point> q;
  for (const auto& f : t.faces)
    for (int k = 0; k < 3; ++k) {
      const Point& a = t.points[f[k]];
      const Point& b = t.points[f[(k + 1) % 3]];
      if ((a.x() < 0) == (b.x() < 0)) continue;
      const double s = a.x() / (a.x() - b.x());
      const Point p = a + s * (b - a);
      q.push_back(p);
    }
  return q;
}

}  // namespace

HeadDimensions measure_head(const Triangles& head, const std::string& what) {
  const std::vector<Point> q = sagittal_profile(head);
  auto best = [&](const char* name, const std::function<bool(const Point&)>& in,
                  const std::function<double(const Point&)>& score) {
    const Point* b = nullptr;
    for (const Point& p : q)
      if (p.z() > 0 && in(p) && (!b || score(p) > score(*b))) b = &p;
    if (!b) throw pipeline::bad_input(what, std::string("cannot find the ") + name +
                                               " on the sagittal profile (is the face toward +z, y up?)");
    return *b;
  };
  auto max_abs_x = [&](const char* name, const std::function<bool(const Point&)>& in) {
    double m = -1;
    for (const Point& p : head.points)
      if (in(p)) m = std::max(m, std::abs(p.x()));
    if (m < 0) throw pipeline::bad_input(what, std::string("no surface in the region of the ") + name);
    return 2 * m;
  };
  HeadDimensions d;
  d.pronasale = best("pronasale", [](const Point&) { return true; }, [](const Point& p) { return p.z(); });
  const Point pr = d.pronasale;
  // Sellion: the deepest point of the profile below the chord from the pronasale to the
  // forehead 70 mm above it (robust to how far the nasal bridge and the brow stick out).
  double z_forehead = -1;
  for (const Point& p : q)
    if (p.z() > 0 && std::abs(p.y() - (pr.y() + 70)) < 3.0) z_forehead = std::max(z_forehead, p.z());
  if (z_forehead < 0) throw pipeline::bad_input(what, "no forehead 70 mm above the nose tip");
  d.sellion = best("sellion", [&](const Point& p) { return p.y() >= pr.y() + 10 && p.y() <= pr.y() + 70; },
                   [&](const Point& p) { return pr.z() + (z_forehead - pr.z()) * (p.y() - pr.y()) / 70.0 - p.z(); });
  d.glabella = best("glabella", [&](const Point& p) { return p.y() >= d.sellion.y() && p.y() <= d.sellion.y() + 40; },
                    [](const Point& p) { return p.z(); });
  d.subnasale = best("subnasale", [&](const Point& p) { return p.y() >= pr.y() - 25 && p.y() <= pr.y() - 5; },
                     [](const Point& p) { return -p.z(); });
  d.menton = best("menton", [&](const Point& p) { return p.y() < pr.y() - 40 && p.z() >= pr.z() - 50; },
                  [](const Point& p) { return -p.y(); });
  const Point se = d.sellion, me = d.menton, sn = d.subnasale;
  d.face_length = std::sqrt(CGAL::squared_distance(se, me));
  d.face_width = max_abs_x("zygion", [&](const Point& p) {
    return p.y() >= pr.y() && p.y() <= se.y() && p.z() >= se.z() - 100;
  });
  d.jaw_width = max_abs_x("gonion", [&](const Point& p) {
    return p.y() >= me.y() + 15 && p.y() <= me.y() + 35 && p.z() >= se.z() - 100;
  });
  d.head_breadth = max_abs_x("euryon", [&](const Point& p) { return p.y() >= se.y() + 25; });
  double zmin = std::numeric_limits<double>::max(), ymax = -zmin;
  for (const Point& p : head.points) ymax = std::max(ymax, p.y());
  for (const Point& p : q)
    if (p.y() >= se.y() - 20) zmin = std::min(zmin, p.z());
  if (zmin == std::numeric_limits<double>::max())
    throw pipeline::bad_input(what, "no back of the head near the sagittal plane");
  d.head_length = d.glabella.z() - zmin;
  d.head_height = ymax - se.y();
  d.nose_protrusion = pr.z() - sn.z();
  d.nose_breadth = max_abs_x("alare", [&](const Point& p) {
    return p.y() >= sn.y() && p.y() <= pr.y() && p.z() >= sn.z() - 8;
  });
  return d;
}

}  // namespace generator
