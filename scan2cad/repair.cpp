// repair: soup → clean manifold surface (steps in repair.h).
#include "scan2cad/repair.h"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/manifoldness.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/smooth_shape.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <sstream>

#include "pipeline/error.h"
#include "pipeline/principal_spreads.h"
#include "pipeline/progress.h"
#include "pipeline/require_affordable_edge.h"
#include "pipeline/soup_to_mesh.h"
#include "pipeline/units.h"
#include "scan2cad/internal/cleanup.h"
#include "scan2cad/remove_support_plane.h"

namespace PMP = CGAL::Polygon_mesh_processing;
using pipeline::SurfaceMesh;

namespace scan2cad {

namespace {

std::size_t count_boundary_loops(const SurfaceMesh& mesh) {
  std::vector<SurfaceMesh::Halfedge_index> loops;
  PMP::extract_boundary_cycles(mesh, std::back_inserter(loops));
  return loops.size();
}

// Isotropic remeshing; on an open shell the border is first split to the target length and
// then protected, so the rim stays where it is (CGAL's recommended recipe).
void remesh(SurfaceMesh& mesh, double target, int iterations) {
  auto constrained = mesh.add_property_map<SurfaceMesh::Edge_index, bool>("e:rf_border", false).first;
  std::vector<SurfaceMesh::Edge_index> border;
  PMP::border_halfedges(faces(mesh), mesh, boost::make_function_output_iterator([&](SurfaceMesh::Halfedge_index h) {
                          border.push_back(mesh.edge(h));
                        }));
  if (!border.empty()) {
    PMP::split_long_edges(border, target, mesh);
    for (auto e : mesh.edges())
      if (mesh.is_border(e)) constrained[e] = true;
  }
  PMP::isotropic_remeshing(faces(mesh), target, mesh,
                           CGAL::parameters::number_of_iterations(iterations)
                               .edge_is_constrained_map(constrained)
                               .protect_constraints(!border.empty()));
  mesh.remove_property_map(constrained);
  mesh.collect_garbage();
}

}  // namespace

SurfaceMesh repair(const pipeline::PolygonSoup& soup, ScanKind kind, const RepairOptions& opt, RepairReport* report_out) {
  RepairReport r;
  r.input_vertices = soup.points.size();
  r.input_faces = soup.polygons.size();
  pipeline::Progress progress("repair", 0);

  // 0. A table or turntable the object stood on: its faces go, before the soup is made a mesh
  //    (which splits the vertices the cut leaves non-manifold).
  pipeline::PolygonSoup without_support;
  if (opt.remove_support) {
    progress.step("support plane (a table or turntable under the object)");
    const SupportPlane support = find_support_plane(soup.points);
    if (support.found) {
      without_support.points = soup.points;
      for (const auto& polygon : soup.polygons)
        if (std::none_of(polygon.begin(), polygon.end(), [&](std::size_t v) { return support.holds(soup.points[v]); }))
          without_support.polygons.push_back(polygon);
      r.support_faces_removed = soup.polygons.size() - without_support.polygons.size();
      pipeline::log("repair", support.removal_line(r.support_faces_removed, "faces"));
    }
  }
  const pipeline::PolygonSoup& input = r.support_faces_removed > 0 ? without_support : soup;

  // 1. Soup → mesh, degenerate faces.
  progress.step("polygon soup to manifold mesh");
  pipeline::SoupStats ss;
  SurfaceMesh mesh = pipeline::soup_to_mesh(input, &ss);
  r.soup_polygons_removed = ss.polygons_removed;
  r.non_manifold_vertices_split = ss.non_manifold_vertices_split;
  const std::size_t f0 = mesh.number_of_faces();
  PMP::remove_degenerate_faces(mesh);
  mesh.collect_garbage();
  r.degenerate_faces_removed = f0 > mesh.number_of_faces() ? f0 - mesh.number_of_faces() : 0;
  if (mesh.number_of_faces() == 0) throw pipeline::bad_input("mesh", "no usable faces after removing degenerate ones");
  // A head squashed flat ended in the smoothing as "shrank the surface to -nan %" (exit 3).
  if (const std::string why = pipeline::why_flat(
          pipeline::principal_spreads(mesh.vertices(), [&](pipeline::VertexIndex v) -> const pipeline::Point& { return mesh.point(v); }),
          "its vertices");
      !why.empty())
    throw pipeline::bad_input("mesh", why);
  // Checked before any work, on the input's area (the hole fills add little).
  pipeline::require_affordable_edge("--edge", opt.target_edge_mm, mesh, max_remeshed_triangles);

  // 2. Small components. A large second piece is no scanner debris: a 4 mm gap across the NIOSH
  //    head cut off its face (36 % of the faces), and repair kept the back of the head and closed
  //    it with exit 0; of two heads one was kept.
  //    The same holds for a piece that cutting out self-intersections severs (steps 4 and 7).
  const auto count_pieces_removed = [&r](const internal::ComponentsKept& kept, const std::string& how) {
    if (kept.second_area_share > max_second_component_share)
      throw pipeline::bad_input("mesh", "the surface is in " + std::to_string(kept.components) + " pieces" + how +
                                            ", and the second largest holds " +
                                            std::to_string(int(std::lround(100 * kept.second_area_share))) +
                                            " % of the area: a scan cut in two, or two objects? repair keeps one piece");
    r.components_removed += kept.components > 0 ? kept.components - 1 : 0;
    r.component_faces_removed += kept.faces_removed;
  };
  count_pieces_removed(internal::keep_largest_component(mesh), "");
  // The edge not so coarse that the object loses its shape (measured without the debris, which
  // made the object look larger): --edge 20 left NIOSH medium 1,126 faces,
  // and align and landmarks ran on it (a gonion 40 mm off), exit 0
  if (const double extent_mm = pipeline::largest_extent(mesh.points());
      opt.target_edge_mm > extent_mm / min_edges_across)
    throw pipeline::Error(pipeline::ErrorKind::usage,
                          "--edge " + pipeline::format_number(opt.target_edge_mm) + " mm is coarser than 1/" +
                              pipeline::format_number(min_edges_across) + " of the object's " +
                              pipeline::format_number(extent_mm) + " mm: the remeshed surface would lose its shape");
  if (const double extent_mm = pipeline::largest_extent(mesh.points());
      opt.max_extent_mm > 0 && extent_mm > opt.max_extent_mm)
    throw pipeline::bad_input("mesh", "it spans " + pipeline::format_number(extent_mm) + " mm, over the " +
                                          pipeline::format_number(opt.max_extent_mm) + " mm of the largest " +
                                          scan_kind_name(kind) + ": " + pipeline::wrong_size_question(true));

  // 3. Spikes.
  progress.step("spikes");
  r.spike_vertices_moved = internal::remove_spikes(mesh, opt.spike_factor);

  // 4. Self-intersections.
  progress.step("self-intersections");
  const internal::SelfIntersectionsCut cut = internal::remove_self_intersecting_faces(mesh);
  r.self_intersecting_faces_before = cut.crossing;
  r.self_intersecting_faces_removed = cut.faces_cut;
  count_pieces_removed(cut.pieces, " once its self-intersecting faces are cut out");

  // 5. Holes.
  progress.step("hole filling");
  std::vector<std::vector<pipeline::FaceIndex>> fills;
  r.holes = fill_holes(mesh, kind, &fills);
  if (kind == ScanKind::head && opt.symmetric_completion && !fills.empty()) {
    progress.step("symmetric completion of " + std::to_string(fills.size()) + " hole fills");
    r.symmetry = complete_fills_by_symmetry(mesh, fills, opt.symmetry);
    r.symmetric_completion_run = true;
  }
  // A flat patch given as a head is closed by a copy of itself: two coincident sheets with nothing
  // inside, on which CGAL 5.5's isotropic remeshing crashes (one triangle did). A head, a sphere
  // (0.094) or a face-only scan closed flat encloses far more than this fraction of area^1.5.
  if (kind == ScanKind::head && CGAL::is_closed(mesh)) {
    const double area_mm2 = PMP::area(mesh);
    if (std::abs(PMP::volume(mesh)) < 1e-3 * std::pow(area_mm2, 1.5))
      throw pipeline::bad_input("mesh", "encloses no volume once its holes are filled: a flat patch, not a head");
  }

  // 6. Relaxation: mean-curvature flow, then isotropic remeshing.
  const double area_before_relaxation_mm2 = PMP::area(mesh);
  if (opt.smoothing_iterations > 0) {
    progress.step("smoothing");
    // CGAL holds no vertex unless given a map ("a default property map where no vertex is
    // constrained"): the respirator's rim moved 3.6 mm at --smooth 30 --smooth-time 0.05 (sweep S).
    auto held = mesh.add_property_map<pipeline::VertexIndex, bool>("v:repair_held", false).first;
    auto before = mesh.add_property_map<pipeline::VertexIndex, pipeline::Point>("v:repair_before").first;
    for (auto v : mesh.vertices()) held[v] = mesh.is_border(v), before[v] = mesh.point(v);
    PMP::smooth_shape(mesh, opt.smoothing_time,
                      CGAL::parameters::number_of_iterations(opt.smoothing_iterations).vertex_is_constrained_map(held));
    for (auto v : mesh.vertices())
      r.smoothing_max_move_mm = std::max(r.smoothing_max_move_mm, std::sqrt(CGAL::squared_distance(before[v], mesh.point(v))));
    mesh.remove_property_map(held);
    mesh.remove_property_map(before);
    // CGAL gives up without a word when its linear solve fails: then nothing moved.
    r.smoothing_iterations = r.smoothing_max_move_mm > 0 ? opt.smoothing_iterations : 0;
    // An open shell with its rim held shrinks toward the disc the rim bounds (--smooth 100
    // --smooth-time 1 left a cap 18 triangles of 3e-13 mm, exit 0); a closed one is scaled back
    // to its volume after each step, so it keeps ~90 % of its area while it rounds into a ball
    // (NIOSH medium at 100 x 1: exit 0, then turned 180 deg by align and a face 158 mm long, sweep S).
    // Relaxing a scan's noise (0.2-0.3 mm) moves vertices by tenths of a mm: the defaults by
    // under 0.01 mm.
    if (const double kept = PMP::area(mesh) / area_before_relaxation_mm2; !(kept > 0.7))
      throw pipeline::algorithm_failed("mesh", "smoothing shrank the surface to " +
                                                   pipeline::format_number(std::round(100 * kept)) +
                                                   " % of its area: --smooth or --smooth-time too strong?");
    if (!(r.smoothing_max_move_mm <= max_smoothing_move_mm))
      throw pipeline::algorithm_failed("mesh", "smoothing moved a vertex " +
                                                   pipeline::format_number(r.smoothing_max_move_mm) + " mm, over " +
                                                   pipeline::format_number(max_smoothing_move_mm) +
                                                   " mm: it reshapes the object; --smooth or --smooth-time too strong?");
  }
  if (opt.target_edge_mm > 0) {
    progress.step("isotropic remeshing to " + pipeline::format_number(opt.target_edge_mm) + " mm");
    remesh(mesh, opt.target_edge_mm, opt.remesh_iterations);
    r.target_edge_mm = opt.target_edge_mm;
  }

  // 7. Self-intersections the remeshing made (rare, at tight folds): cut out and refill. The last
  //    count is the final check (a full test of a 200k-face head costs about a second).
  progress.step("self-intersection check of the remeshed surface");
  std::size_t crossing = internal::count_self_intersecting_faces(mesh);
  for (int round = 0; round < 3 && crossing > 0; ++round) {
    progress.step("removing self-intersections created by remeshing, round " + std::to_string(round + 1));
    const internal::SelfIntersectionsCut remeshing_cut = internal::remove_self_intersecting_faces(mesh);
    r.self_intersecting_faces_removed += remeshing_cut.faces_cut;
    count_pieces_removed(remeshing_cut.pieces, " once the self-intersecting faces of its remeshing are cut out");
    for (const auto& h : fill_holes(mesh, kind))
      if (!h.kept_open) r.holes.push_back(h);
    crossing = internal::count_self_intersecting_faces(mesh);
  }

  // Checks and orientation.
  r.closed = CGAL::is_closed(mesh);
  if (r.closed && !PMP::is_outward_oriented(mesh)) PMP::reverse_face_orientations(mesh);
  r.self_intersecting_after = crossing > 0;
  // a Surface_mesh is edge-manifold by construction; vertices are checked here
  std::vector<SurfaceMesh::Halfedge_index> nm;
  PMP::non_manifold_vertices(mesh, std::back_inserter(nm));
  r.manifold = nm.empty();
  r.boundary_loops_after = count_boundary_loops(mesh);
  r.output_vertices = mesh.number_of_vertices();
  r.output_faces = mesh.number_of_faces();
  double total = 0;
  for (auto e : mesh.edges()) total += PMP::edge_length(e, mesh);
  r.mean_edge_mm = mesh.number_of_edges() ? total / double(mesh.number_of_edges()) : 0;
  r.area_mm2 = PMP::area(mesh);
  r.volume_mm3 = r.closed ? PMP::volume(mesh) : 0;
  // step, not finish: the program has yet to write the mesh, and a failed write must not follow a "done"
  progress.step("repaired: " + std::to_string(r.output_faces) + " triangles, " + (r.closed ? "closed" : "open"));
  if (report_out) *report_out = r;

  if (kind == ScanKind::head && !r.closed)
    throw pipeline::algorithm_failed("mesh", std::to_string(r.boundary_loops_after) +
                                                 " boundary loops remain, expected a closed head surface");
  // A hole CGAL could not fill stays open (fill_holes.h); beside the rim it reached surface_mesh
  // as a hole too small to mesh.
  if (kind == ScanKind::respirator && r.boundary_loops_after > 1)
    throw pipeline::algorithm_failed("mesh", std::to_string(r.boundary_loops_after - 1) +
                                                 " holes remain open beside the rim, expected only the rim");
  if (!r.manifold)
    throw pipeline::algorithm_failed("mesh", std::to_string(nm.size()) + " non-manifold vertices remain");
  if (r.self_intersecting_after)
    throw pipeline::algorithm_failed("mesh", "self-intersections remain after 3 rounds of repair");
  return mesh;
}

nlohmann::json RepairReport::to_json() const {
  nlohmann::json holes_j = nlohmann::json::array();
  for (const auto& h : holes)
    holes_j.push_back({{"boundary_edges", h.boundary_edges}, {"perimeter_mm", h.perimeter_mm},
                       {"diameter_mm", h.diameter_mm}, {"kept_open", h.kept_open}, {"filled", h.filled},
                       {"faired", h.faired}, {"faces_added", h.faces_added}});
  std::size_t filled = 0;
  for (const auto& h : holes) filled += h.filled;
  return {{"input", {{"vertices", input_vertices}, {"faces", input_faces}}},
          {"support_faces_removed", support_faces_removed},
          {"soup_polygons_removed", soup_polygons_removed},
          {"non_manifold_vertices_split", non_manifold_vertices_split},
          {"degenerate_faces_removed", degenerate_faces_removed},
          {"small_components_removed", components_removed},
          {"small_component_faces_removed", component_faces_removed},
          {"spike_vertices_moved", spike_vertices_moved},
          {"self_intersecting_faces_before", self_intersecting_faces_before},
          {"self_intersecting_faces_removed", self_intersecting_faces_removed},
          {"holes_filled", filled},
          {"holes", holes_j},
          {"symmetric_completion", symmetric_completion_run ? symmetry.to_json() : nlohmann::json()},
          {"smoothing_iterations", smoothing_iterations},
          {"smoothing_max_move_mm", smoothing_max_move_mm},
          {"target_edge_mm", target_edge_mm},
          {"mean_edge_mm", mean_edge_mm},
          {"output", {{"vertices", output_vertices}, {"faces", output_faces}}},
          {"boundary_loops_after", boundary_loops_after},
          {"closed", closed},
          {"manifold", manifold},
          {"self_intersecting_after", self_intersecting_after},
          {"area_mm2", area_mm2},
          {"volume_mm3", volume_mm3}};
}

std::string RepairReport::summary() const {
  std::size_t filled = 0, completed = 0;
  for (const auto& h : holes) filled += h.filled;
  for (const auto& h : symmetry.holes) completed += h.completed;
  std::ostringstream s;
  s << "in " << input_faces << " faces; removed: ";
  if (support_faces_removed > 0) s << support_faces_removed << " faces of a table, ";
  s << soup_polygons_removed << " soup polygons, "
    << degenerate_faces_removed << " degenerate faces, " << components_removed << " small components ("
    << component_faces_removed << " faces), " << self_intersecting_faces_removed << " self-intersecting faces; "
    << spike_vertices_moved << " spike vertices moved; " << filled << " holes filled";
  if (symmetric_completion_run)
    s << " (" << completed << " completed by symmetry" << (symmetry.skipped.empty() ? "" : ": " + symmetry.skipped) << ")";
  s << "; out " << output_faces
    << " faces, mean edge " << mean_edge_mm << " mm, " << (closed ? "closed" : "open") << ", "
    << (manifold ? "manifold" : "NON-manifold") << ", "
    << (self_intersecting_after ? "self-intersecting" : "no self-intersections");
  return s.str();
}

std::string RepairReport::large_fill_warning(double min_diameter_mm) const {
  const HoleInfo* largest = nullptr;
  for (const auto& h : holes)
    if (h.filled && !h.kept_open && h.diameter_mm >= min_diameter_mm && (!largest || h.diameter_mm > largest->diameter_mm))
      largest = &h;
  if (!largest) return "";
  return "a hole " + pipeline::format_number(std::round(largest->diameter_mm)) + " mm across was filled (" +
         std::to_string(largest->faces_added) +
         " faces): that part of the surface is a faired patch, not the scan (the back of a face-only scan?); a "
         "strap laid over it follows the patch, and its stretch with it";
}

}  // namespace scan2cad
