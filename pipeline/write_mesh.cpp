#include "pipeline/write_mesh.h"

#include <CGAL/IO/PLY.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/IO/write_ply_points.h>

#include <fstream>

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"
#include "pipeline/lower_extension.h"

namespace pipeline {

namespace {

// Writes `path` atomically: a .ply through write_ply(stream) in binary, any other extension
// through write_other(temporary path), where CGAL picks the format from the extension.
template <class WritePly, class WriteOther>
void write_mesh_by_extension(const std::string& path, WritePly write_ply, WriteOther write_other) {
  const std::string ext = lower_extension(path);
  write_atomic(path, [&](const std::string& tmp) {
    bool ok;
    if (ext == ".ply") {
      std::ofstream out(tmp, std::ios::binary);
      CGAL::IO::set_binary_mode(out);
      ok = write_ply(out) && out.flush();
    } else {
      ok = write_other(tmp);
    }
    if (!ok) throw io_failed(path, "cannot write mesh (format '" + ext + "'): " + why_write_failed());
  });
}

}  // namespace

void write_surface_mesh(const std::string& path, const SurfaceMesh& mesh) {
  write_mesh_by_extension(
      path, [&](std::ostream& out) { return CGAL::IO::write_PLY(out, mesh); },
      [&](const std::string& tmp) {
        return CGAL::IO::write_polygon_mesh(tmp, mesh, CGAL::parameters::stream_precision(17));
      });
}

void write_polygon_soup(const std::string& path, const PolygonSoup& soup) {
  write_mesh_by_extension(
      path, [&](std::ostream& out) { return CGAL::IO::write_PLY(out, soup.points, soup.polygons); },
      [&](const std::string& tmp) {
        return CGAL::IO::write_polygon_soup(tmp, soup.points, soup.polygons, CGAL::parameters::stream_precision(17));
      });
}

void write_point_cloud(const std::string& path, const PointCloud& cloud) {
  const std::string ext = lower_extension(path);
  write_atomic(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    const bool normals = cloud.normals.size() == cloud.points.size() && !cloud.points.empty();
    if (ext == ".xyz") {
      out.precision(9);
      for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        out << cloud.points[i];
        if (normals) out << ' ' << cloud.normals[i];
        out << '\n';
      }
    } else if (ext == ".ply") {
      CGAL::IO::set_binary_mode(out);
      using PN = std::pair<Point, Vector>;
      std::vector<PN> pn(cloud.points.size());
      for (std::size_t i = 0; i < pn.size(); ++i)
        pn[i] = {cloud.points[i], normals ? cloud.normals[i] : Vector(0, 0, 0)};
      if (normals)
        CGAL::IO::write_PLY(out, pn, CGAL::parameters::point_map(CGAL::First_of_pair_property_map<PN>())
                                         .normal_map(CGAL::Second_of_pair_property_map<PN>()));
      else
        CGAL::IO::write_PLY(out, pn, CGAL::parameters::point_map(CGAL::First_of_pair_property_map<PN>()));
    } else {
      throw io_failed(path, "unknown point cloud format '" + ext + "', expected .ply or .xyz");
    }
    out.flush();
    if (!out) throw io_failed(path, "write failed: " + why_write_failed());
  });
}

}  // namespace pipeline
