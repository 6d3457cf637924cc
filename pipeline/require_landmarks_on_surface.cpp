#include "pipeline/require_landmarks_on_surface.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

#include <cmath>

#include "pipeline/error.h"

namespace pipeline {

void require_landmarks_on_surface(const std::map<std::string, Landmark>& landmarks, const SurfaceMesh& surface,
                                  const std::string& path, double max_mm, std::map<std::string, double>* distances_mm) {
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>>>;
  if (surface.number_of_faces() == 0) throw bad_input(path, "no surface to check the landmarks against");
  Tree tree(faces(surface).first, faces(surface).second, surface);
  tree.accelerate_distance_queries();
  for (const auto& [name, l] : landmarks) {
    const double d = std::sqrt(tree.squared_distance(Point(l.position.x(), l.position.y(), l.position.z())));
    if (distances_mm) (*distances_mm)[name] = d;
    if (!(d <= max_mm))
      throw bad_input(path, "landmark " + name + " is " + format_number(d) + " mm from the head surface, expected <= " +
                                format_number(max_mm) + " mm (same frame as the aligned head?)");
  }
}

}  // namespace pipeline
