// scan2cad::load_surface_any_unit (declared in align.h): any scan file → triangle mesh in mm.
#include <CGAL/Polygon_mesh_processing/orientation.h>

#include <utility>

#include "pipeline/error.h"
#include "pipeline/read_scan.h"
#include "pipeline/soup_to_mesh.h"
#include "scan2cad/align.h"

namespace scan2cad {

pipeline::SurfaceMesh load_surface_any_unit(const std::string& path, double expected_size_mm,
                                            pipeline::Unit* unit_read, pipeline::Unit unit) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  pipeline::ScanReadOptions ro;
  ro.expected_size_mm = expected_size_mm;
  ro.unit = unit;
  pipeline::Scan scan = pipeline::read_scan(path, ro);
  if (!scan.is_mesh)
    throw pipeline::bad_input(path, "is a point cloud, expected a surface mesh (run reconstruct and repair first)");
  if (unit_read) *unit_read = scan.unit;
  pipeline::SurfaceMesh mesh = pipeline::naming_file(path, [&] { return pipeline::soup_to_mesh(std::move(scan.soup)); });
  if (mesh.number_of_faces() == 0)
    throw pipeline::bad_input(path, "no usable faces after soup repair");
  // Outward normals when the surface is closed (landmarks read "facing down" from them).
  if (CGAL::is_closed(mesh)) PMP::orient_to_bound_a_volume(mesh);
  return mesh;
}

}  // namespace scan2cad
