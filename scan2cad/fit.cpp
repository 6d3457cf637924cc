#include "scan2cad/fit.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Polygon_mesh_processing/angle_and_area_smoothing.h>
#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "pipeline/error.h"
#include "pipeline/require_cheeks_on_their_sides.h"
#include "scan2cad/internal/number_topology.h"

namespace scan2cad {

using pipeline::SurfaceMesh;
namespace PMP = CGAL::Polygon_mesh_processing;

namespace {

const char* head_names[] = {"back_of_head", "forehead", "left_cheek", "right_cheek", "chin"};

// The triangles of part `label` (label < 0: every face).
std::vector<pipeline::Kernel::Triangle_3> part_triangles(const SurfaceMesh& m, int label) {
  const auto part = m.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
  std::vector<pipeline::Kernel::Triangle_3> out;
  for (auto f : m.faces())
    if (label < 0 || part[f] == label) {
      auto h = m.halfedge(f);
      out.emplace_back(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h))));
    }
  return out;
}

// One constrained isotropic remeshing pass over the faces `selected` picks: `constrained` edges
// are split and collapsed along, never cut across or moved off; `patch` keeps every patch's
// outline (a face's patch is never changed). Used by remesh_parts (patch = part) and fit_parts
// (patch = 2 part + refined).
void remesh_selected(SurfaceMesh& mesh, const std::function<bool(pipeline::FaceIndex)>& selected, double edge_mm,
                     int iterations, SurfaceMesh::Property_map<pipeline::FaceIndex, int> patch,
                     SurfaceMesh::Property_map<SurfaceMesh::Edge_index, bool> constrained) {
  std::vector<pipeline::FaceIndex> faces;
  for (auto f : mesh.faces())
    if (selected(f)) faces.push_back(f);
  PMP::isotropic_remeshing(faces, edge_mm, mesh,
                           CGAL::parameters::number_of_iterations(iterations)
                               .edge_is_constrained_map(constrained)
                               .face_patch_map(patch)
                               .relax_constraints(true));
  mesh.collect_garbage();
}

}  // namespace

std::size_t mark_border_corners(const SurfaceMesh& mesh, double min_turn_deg, double jog_mm,
                                SurfaceMesh::Property_map<pipeline::VertexIndex, bool> corner) {
  const double min_turn = min_turn_deg * M_PI / 180.0;
  std::vector<bool> seen(mesh.number_of_halfedges(), false);
  std::size_t unmarked = 0;
  for (auto start : mesh.halfedges()) {
    if (!mesh.is_border(start) || seen[std::size_t(start)]) continue;
    // One border loop: its vertices (target of each border halfedge), the length of the edge
    // leading to each, and the signed turn there (sign from the surface normal, so that a
    // turn to the left and one back to the right cancel).
    std::vector<pipeline::VertexIndex> v;
    std::vector<double> turn, edge_len;
    for (auto h = start;;) {
      seen[std::size_t(h)] = true;
      const auto& a = mesh.point(mesh.source(h));
      const auto& b = mesh.point(mesh.target(h));
      const auto& c = mesh.point(mesh.target(mesh.next(h)));
      const pipeline::Vector u = b - a, w = c - b;
      const double lu = std::sqrt(u.squared_length()), lw = std::sqrt(w.squared_length());
      const double angle = std::acos(std::clamp((u * w) / std::max(lu * lw, 1e-300), -1.0, 1.0));
      const auto n = PMP::compute_vertex_normal(mesh.target(h), mesh);
      v.push_back(mesh.target(h));
      edge_len.push_back(lu);
      turn.push_back(CGAL::cross_product(u, w) * n >= 0 ? angle : -angle);
      h = mesh.next(h);
      if (h == start) break;
    }
    const std::size_t n = v.size();
    std::vector<bool> is_corner(n);
    for (std::size_t i = 0; i < n; ++i) is_corner[i] = !(std::abs(turn[i]) < min_turn);
    // A jog: corners within jog_mm of each other along the loop whose turns add up to less than
    // min_turn (a 1 mm step in the generated three-size XL cup's rim, turns of 66 and -72 deg,
    // left a gamma 0.29 triangle, since fixed corners cannot be collapsed). It is scanner noise,
    // not a corner, so its vertices stay free; the remeshing then collapses the step.
    std::vector<bool> jog(n, false);
    for (std::size_t i = 0; i < n; ++i) {
      if (!is_corner[i]) continue;
      double arc = 0, sum = turn[i];
      for (std::size_t k = 1; k < n; ++k) {
        const std::size_t j = (i + k) % n;
        arc += edge_len[j];
        if (arc > jog_mm) break;
        sum += turn[j];
        if (is_corner[j] && std::abs(sum) < min_turn)
          for (std::size_t m = 0; m <= k; ++m) jog[(i + m) % n] = true;
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      corner[v[i]] = is_corner[i] && !jog[i];
      unmarked += is_corner[i] && jog[i];
    }
  }
  return unmarked;
}

std::string fit_part_name(int label, const std::string& kind) {
  return kind == "head" ? head_names[label] : "respirator_inner";
}

void check_parts(const SurfaceMesh& mesh, const std::string& kind) {
  auto found = mesh.property_map<pipeline::FaceIndex, int>(pipeline::part_property);
  if (!found.second) {
    // segment writes an int; one of another type was reported as missing
    const auto names = mesh.properties<pipeline::FaceIndex>();
    if (std::find(names.begin(), names.end(), pipeline::part_property) != names.end())
      throw pipeline::bad_input("parts", "face property \"part\" is not an int (segment writes int labels)");
    throw pipeline::bad_input("parts", "no face property \"part\" (run segment first)");
  }
  std::array<bool, 5> present{};
  for (auto f : mesh.faces()) {
    const int l = found.first[f];
    if (kind == "head" ? (l < 0 || l > 4) : l != 0)
      throw pipeline::bad_input("parts", "face " + std::to_string(std::size_t(f)) + " has part " +
                                             std::to_string(l) + ", not a " + kind + " part label");
    if (mesh.degree(f) != 3)
      throw pipeline::bad_input("parts", "face " + std::to_string(std::size_t(f)) + " is not a triangle");
    present[std::size_t(l)] = true;
  }
  // A respirator's single part has the label of a head's back_of_head: given as a head, it was
  // fitted and meshed as a head with no face.
  if (kind == "head")
    for (int l = 0; l < 5; ++l)
      if (!present[std::size_t(l)])
        throw pipeline::bad_input("parts", std::string("no face of part ") + head_names[l] +
                                               ": a segmented head has all five (is this a respirator?)");
  // segment leaves each part one connected piece (islands merged), and fit keeps it so. Labels
  // scrambled face by face had fit keep ~190,000 cut edges, and surface_mesh then ran for over
  // 11 minutes on the medium head's 5 "parts" before it was stopped.
  std::vector<std::size_t> piece_of(mesh.num_faces());  // by face index (the mesh is const)
  std::vector<char> cut(mesh.num_edges(), 0);
  for (auto e : mesh.edges())
    cut[e] = !mesh.is_border(e) && found.first[mesh.face(mesh.halfedge(e))] !=
                                       found.first[mesh.face(mesh.opposite(mesh.halfedge(e)))];
  PMP::connected_components(mesh, CGAL::make_property_map(piece_of),
                            CGAL::parameters::edge_is_constrained_map(CGAL::make_property_map(cut)));
  std::map<int, std::set<std::size_t>> pieces_of_part;
  for (auto f : mesh.faces()) pieces_of_part[found.first[f]].insert(piece_of[f]);
  for (const auto& [label, pieces] : pieces_of_part)
    if (pieces.size() > 1)
      throw pipeline::bad_input("parts", "part " + fit_part_name(label, kind) + " is in " + std::to_string(pieces.size()) +
                                             " separate pieces, but segment makes each part one connected piece "
                                             "(labels scrambled or edited by hand?)");
  if (kind == "head") {
    double x_sum[5] = {0, 0, 0, 0, 0}, n[5] = {0, 0, 0, 0, 0};
    for (auto f : mesh.faces()) {
      const std::size_t l = std::size_t(found.first[f]);
      for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) x_sum[l] += mesh.point(v).x(), n[l] += 1;
    }
    pipeline::require_cheeks_on_their_sides("parts", "part", x_sum[2] / n[2], x_sum[3] / n[3]);
  }
}

SurfaceMesh remesh_parts(const SurfaceMesh& input, const std::string& kind, double edge_mm, double back_edge_mm) {
  check_parts(input, kind);
  SurfaceMesh mesh = input;
  mesh.collect_garbage();
  auto part = mesh.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
  auto constrained = mesh.add_property_map<SurfaceMesh::Edge_index, bool>("e:fit_cut", false).first;
  auto mark = [&] {
    for (auto e : mesh.edges()) {
      const auto h = mesh.halfedge(e);
      constrained[e] = mesh.is_border(e) || part[mesh.face(h)] != part[mesh.face(mesh.opposite(h))];
    }
  };
  mark();
  if (kind == "respirator") {
    // Sharp creases of a respirator's inner face (CAD parts: the fold of the real Flex face seal's
    // lip, 2.1 mm off when remeshed across) are kept as constrained polylines.
    for (auto e : mesh.edges()) {
      if (mesh.is_border(e)) continue;
      const auto h = mesh.halfedge(e);
      const auto n1 = PMP::compute_face_normal(mesh.face(h), mesh),
                 n2 = PMP::compute_face_normal(mesh.face(mesh.opposite(h)), mesh);
      if (n1 * n2 < std::cos(45.0 * M_PI / 180.0)) constrained[e] = true;
    }
  }
  // Corners of an open border (a respirator's inner face: where its rim turns sharply, > 20 deg)
  // are kept fixed: relaxing and collapsing along the rim polyline would cut them off (1.8 mm
  // on the real Flex face seal). Closed heads have no border, so nothing is fixed there. Steps
  // shorter than a quarter edge are noise and stay free (see mark_border_corners).
  auto corner = mesh.add_property_map<pipeline::VertexIndex, bool>("v:fit_corner", false).first;
  mark_border_corners(mesh, 20.0, 0.25 * edge_mm, corner);
  PMP::isotropic_remeshing(mesh.faces(), edge_mm, mesh,
                           CGAL::parameters::number_of_iterations(3)
                               .edge_is_constrained_map(constrained)
                               .vertex_is_constrained_map(corner)
                               .face_patch_map(part)
                               .relax_constraints(true));
  mesh.collect_garbage();
  mesh.remove_property_map(corner);
  if (kind == "head" && back_edge_mm > 0) {
    // Coarser back of head, then the face parts once more: the cut is constrained (kept) but its
    // edges may be collapsed by the back pass; the last pass re-splits them to the face size and
    // relaxes the face-side triangles the collapses distorted. (Protecting the cut instead leaves
    // gamma ~0.2 triangles on the back side.)
    mark();
    remesh_selected(mesh, [&](pipeline::FaceIndex f) { return part[f] == 0; }, back_edge_mm, 3, part, constrained);
    mark();
    remesh_selected(mesh, [&](pipeline::FaceIndex f) { return part[f] != 0; }, edge_mm, 3, part, constrained);
  }
  mesh.remove_property_map(constrained);
  return mesh;
}

SurfaceMesh fit_parts(const SurfaceMesh& input, const std::string& kind, double edge_mm, double refine_above_mm,
                      std::size_t* refined_faces) {
  if (refined_faces) *refined_faces = 0;
  if (kind != "head") return remesh_parts(input, kind, edge_mm);  // the rim needs remesh_parts' corner handling
  check_parts(input, kind);
  // Patch id = 2 part + (in the refined region): every patch outline, and every sharp edge
  // (> 60 deg between the face normals, e.g. the bottom of the neck), is a constrained polyline
  // that the remeshing splits and collapses along but never cuts across. CGAL keeps the
  // constraint flags of split edges, so they are set once. (CGAL 5.5's isotropic remeshing has
  // one target length per call; its curvature-adaptive sizing came in 5.6, hence the region.)
  auto prepare = [&](SurfaceMesh& mesh, const std::function<bool(pipeline::VertexIndex)>& fine) {
    mesh.collect_garbage();
    const auto part = mesh.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
    auto patch = mesh.add_property_map<pipeline::FaceIndex, int>("f:fit_patch", 0).first;
    std::size_t n = 0;
    for (auto f : mesh.faces()) {
      bool in = false;
      for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) in = in || fine(v);
      patch[f] = 2 * part[f] + (in ? 1 : 0);
      n += in;
    }
    auto constrained = mesh.add_property_map<SurfaceMesh::Edge_index, bool>("e:fit_constrained", false).first;
    PMP::detect_sharp_edges(mesh, 60.0, constrained);
    for (auto e : mesh.edges()) {
      const auto h = mesh.halfedge(e);
      constrained[e] = constrained[e] || mesh.is_border(e) || patch[mesh.face(h)] != patch[mesh.face(mesh.opposite(h))];
    }
    return n;
  };
  auto remesh_where = [&](SurfaceMesh& mesh, bool fine_region, double edge, int iterations) {
    auto patch = mesh.property_map<pipeline::FaceIndex, int>("f:fit_patch").first;
    auto constrained = mesh.property_map<SurfaceMesh::Edge_index, bool>("e:fit_constrained").first;
    remesh_selected(mesh, [&](pipeline::FaceIndex f) { return (patch[f] % 2 == 1) == fine_region; }, edge, iterations,
                    patch, constrained);
  };
  auto finish = [&](SurfaceMesh& mesh) {
    auto part = mesh.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
    auto patch = mesh.property_map<pipeline::FaceIndex, int>("f:fit_patch").first;
    for (auto f : mesh.faces()) part[f] = patch[f] / 2;
    mesh.remove_property_map(patch);
    auto constrained = mesh.property_map<SurfaceMesh::Edge_index, bool>("e:fit_constrained").first;
    mesh.remove_property_map(constrained);
  };
  // 1. Uniform fit.
  SurfaceMesh coarse = input;
  prepare(coarse, [](pipeline::VertexIndex) { return false; });
  remesh_where(coarse, false, edge_mm, 3);
  finish(coarse);
  if (!(refine_above_mm > 0)) return coarse;
  // 2. Where does it miss the input? Distances of the input's vertices to it.
  using Triangles = std::vector<pipeline::Kernel::Triangle_3>;
  using Primitive = CGAL::AABB_triangle_primitive<pipeline::Kernel, Triangles::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel, Primitive>>;
  const Triangles coarse_triangles = part_triangles(coarse, -1);
  Tree tree(coarse_triangles.begin(), coarse_triangles.end());
  tree.accelerate_distance_queries();
  SurfaceMesh mesh = input;
  mesh.collect_garbage();
  auto fine = mesh.add_property_map<pipeline::VertexIndex, bool>("v:fit_fine", false).first;
  bool any = false;
  for (auto v : mesh.vertices())
    if (tree.squared_distance(mesh.point(v)) > refine_above_mm * refine_above_mm) fine[v] = any = true;
  // ... and of its vertices and triangle centroids to the input (a triangle bridging a groove,
  // e.g. behind an ear, misses by its middle): then the nearest input face's vertices.
  using FaceTree =
      CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel, CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>>>;
  FaceTree input_tree(faces(mesh).first, faces(mesh).second, mesh);
  input_tree.accelerate_distance_queries();
  auto flag_near = [&](const pipeline::Point& q) {
    const auto hit = input_tree.closest_point_and_primitive(q);
    if (CGAL::squared_distance(q, hit.first) <= refine_above_mm * refine_above_mm) return;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(hit.second), mesh)) fine[v] = true;
    any = true;
  };
  for (auto v : coarse.vertices()) flag_near(coarse.point(v));
  for (const auto& t : coarse_triangles) flag_near(CGAL::centroid(t));
  if (!any) return coarse;
  // Grown by ~2 coarse edges, so that the size grades from fine to coarse inside the region.
  double edge_sum = 0;
  for (auto e : mesh.edges()) edge_sum += std::sqrt(CGAL::squared_distance(mesh.point(mesh.vertex(e, 0)), mesh.point(mesh.vertex(e, 1))));
  const int rings = int(std::ceil(2 * edge_mm / (edge_sum / double(mesh.number_of_edges()))));
  for (int r = 0; r < rings; ++r) {
    std::vector<pipeline::VertexIndex> grow;
    for (auto v : mesh.vertices())
      if (!fine[v])
        for (auto w : CGAL::vertices_around_target(mesh.halfedge(v), mesh))
          if (fine[w]) { grow.push_back(v); break; }
    for (auto v : grow) fine[v] = true;
  }
  // 3. The input again: the region at half the edge (a quarter of the chord error ~ edge^2
  //    curvature / 8), the rest at the edge, the region once more (the coarse pass collapses the
  //    shared outline's edges to its own size).
  const std::size_t n = prepare(mesh, [&](pipeline::VertexIndex v) { return fine[v]; });
  if (refined_faces) *refined_faces = n;
  mesh.remove_property_map(fine);
  remesh_where(mesh, true, edge_mm / 2, 3);
  remesh_where(mesh, false, edge_mm, 3);
  remesh_where(mesh, true, edge_mm / 2, 1);
  finish(mesh);
  // The vertices on the region's outline were re-projected onto the previous pass's output, not
  // onto the input (1.2 mm off at the top of an ear on the generated small head): every vertex
  // goes back onto the input.
  FaceTree original(faces(input).first, faces(input).second, input);
  original.accelerate_distance_queries();
  for (auto v : mesh.vertices()) mesh.point(v) = original.closest_point(mesh.point(v));
  return mesh;
}

double triangle_gamma(const pipeline::Point& p0, const pipeline::Point& p1, const pipeline::Point& p2) {
  const double a = std::sqrt(CGAL::squared_distance(p1, p2)), b = std::sqrt(CGAL::squared_distance(p0, p2)),
               c = std::sqrt(CGAL::squared_distance(p0, p1)), s = (a + b + c) / 2;
  const double area2 = s * (s - a) * (s - b) * (s - c);  // Heron, squared area
  if (!(area2 > 0)) return 0;
  const double area = std::sqrt(area2), r = area / s, R = a * b * c / (4 * area);
  return 2 * r / R;
}

double min_triangle_gamma(const SurfaceMesh& mesh) {
  double worst = 1;
  for (auto f : mesh.faces()) {
    const auto h = mesh.halfedge(f);
    worst = std::min(worst, triangle_gamma(mesh.point(mesh.source(h)), mesh.point(mesh.target(h)),
                                           mesh.point(mesh.target(mesh.next(h)))));
  }
  return worst;
}

namespace {

pipeline::Vector unit_normal(const pipeline::Point& a, const pipeline::Point& b, const pipeline::Point& c) {
  const pipeline::Vector n = CGAL::cross_product(b - a, c - a);
  const double l = std::sqrt(n.squared_length());
  return l > 0 ? n / l : n;
}

// Within 20 deg of coplanar: flips and collapses are only made where they keep the surface.
const double coplanar_cos = std::cos(20.0 * M_PI / 180.0);

// A border edge, or an edge between two parts.
bool is_cut(const SurfaceMesh& mesh, SurfaceMesh::Property_map<pipeline::FaceIndex, int> part,
            SurfaceMesh::Edge_index e) {
  const auto h = mesh.halfedge(e);
  return mesh.is_border(e) || part[mesh.face(h)] != part[mesh.face(mesh.opposite(h))];
}

// Collapses `free_vertex` into its neighbour `kept` if that is a valid collapse (CGAL's link
// condition) and raises the worst triangle around `free_vertex` without turning any remaining
// triangle by more than 20 deg. `kept` stays where it is.
bool collapse_if_better(SurfaceMesh& mesh, pipeline::VertexIndex free_vertex, pipeline::VertexIndex kept) {
  const auto to_kept = mesh.halfedge(free_vertex, kept);
  if (to_kept == SurfaceMesh::null_halfedge() || !CGAL::Euler::does_satisfy_link_condition(mesh.edge(to_kept), mesh))
    return false;
  const pipeline::Point kept_at = mesh.point(kept);
  double worst_before = 1, worst_after = 1;
  for (auto h : CGAL::halfedges_around_target(mesh.halfedge(free_vertex), mesh)) {
    if (mesh.is_border(h)) return false;  // free vertices are interior; guard anyway
    // The face of h is (source(h), free_vertex, w) in its orientation.
    const auto u = mesh.source(h), w = mesh.target(mesh.next(h));
    const auto &pu = mesh.point(u), &pv = mesh.point(free_vertex), &pw = mesh.point(w);
    worst_before = std::min(worst_before, triangle_gamma(pu, pv, pw));
    if (u == kept || w == kept) continue;  // the two faces at the collapsed edge disappear
    const double g = triangle_gamma(pu, kept_at, pw);
    if (unit_normal(pu, kept_at, pw) * unit_normal(pu, pv, pw) < coplanar_cos) return false;
    worst_after = std::min(worst_after, g);
  }
  if (!(worst_after > worst_before)) return false;
  const auto moved = CGAL::Euler::collapse_edge(mesh.edge(to_kept), mesh);
  // collapse_edge keeps the target of the edge's first halfedge, which may be free_vertex's
  // index: the kept vertex (whichever index it has) goes where `kept` was.
  mesh.point(moved) = kept_at;
  return true;
}

}  // namespace

std::size_t collapse_slivers_at_cuts(SurfaceMesh& mesh, double below_gamma) {
  const auto part = mesh.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
  // Why by hand: CGAL's isotropic remeshing never collapses into a constrained polyline's
  // vertices in a way that removes such a sliver (its long edge is constrained, so no flip
  // either), and angle smoothing cannot pull a vertex out of a 180 deg corner: the vertex sits
  // between the two border vertices on a straight border edge (gamma 0.047 on the twosize-m
  // respirator rim). Collapsing it into the nearer end of that edge keeps the border as it is.
  // An ear of a part boundary: a sliver of part P whose two short edges lie on the cut to one
  // part Q, its vertex between them touching no other P face (a cut that bends by ~170 deg
  // there: gamma 0.073 beside the nose of the generated short/wide head). No flip or collapse
  // may touch it (its short edges are on the cut, its vertex is on the cut). Handing the face to
  // Q moves the boundary onto the long edge (by the sliver's height, < 1 mm) and leaves the
  // interior-vertex sliver that the collapse below removes.
  for (auto f : mesh.faces()) {
    const auto h0 = mesh.halfedge(f);
    if (!(triangle_gamma(mesh.point(mesh.source(h0)), mesh.point(mesh.target(h0)), mesh.point(mesh.target(mesh.next(h0)))) <
          below_gamma))
      continue;
    for (auto h : CGAL::halfedges_around_face(h0, mesh)) {
      const auto g1 = mesh.face(mesh.opposite(h)), g2 = mesh.face(mesh.opposite(mesh.next(h)));
      const auto g3 = mesh.face(mesh.opposite(mesh.prev(h)));
      if (g1 == SurfaceMesh::null_face() || g2 == SurfaceMesh::null_face() || g3 == SurfaceMesh::null_face()) continue;
      const int q = part[g1];
      if (q == part[f] || part[g2] != q || part[g3] != part[f]) continue;  // h, next(h) on the cut to q
      int p_faces = 0;  // faces of part[f] around the vertex between the two cut edges (target of h)
      for (auto g : CGAL::faces_around_target(h, mesh)) p_faces += g != SurfaceMesh::null_face() && part[g] == part[f];
      if (p_faces != 1) continue;
      part[f] = q;
      break;
    }
  }
  std::vector<pipeline::FaceIndex> slivers;
  for (auto f : mesh.faces()) {
    const auto h = mesh.halfedge(f);
    if (triangle_gamma(mesh.point(mesh.source(h)), mesh.point(mesh.target(h)), mesh.point(mesh.target(mesh.next(h)))) <
        below_gamma)
      slivers.push_back(f);
  }
  std::size_t collapsed = 0;
  for (auto f : slivers) {
    if (mesh.is_removed(f)) continue;
    for (auto h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh)) {
      if (!is_cut(mesh, part, mesh.edge(h))) continue;
      const auto a = mesh.source(h), b = mesh.target(h), v = mesh.target(mesh.next(h));
      bool free = true;  // on no cut: every face around it in one part, none on the border
      for (auto hv : CGAL::halfedges_around_target(mesh.halfedge(v), mesh))
        free = free && !is_cut(mesh, part, mesh.edge(hv));
      if (!free) continue;
      const bool a_nearer =
          CGAL::squared_distance(mesh.point(v), mesh.point(a)) <= CGAL::squared_distance(mesh.point(v), mesh.point(b));
      if (collapse_if_better(mesh, v, a_nearer ? a : b) || collapse_if_better(mesh, v, a_nearer ? b : a)) {
        ++collapsed;
        break;  // f is gone
      }
    }
  }
  // A flat ear on the rim: a border vertex with a single triangle, lying (almost) on the segment
  // between its two border neighbours (gamma 0.000 on the twosize-m rim: edges 1.51 / 1.51 /
  // 3.02 mm, collinear). Removing that triangle makes the segment the border; the rim moves by
  // the ear's height, allowed up to 2 % of the segment.
  for (auto v : mesh.vertices()) {
    if (mesh.is_removed(v) || !mesh.is_border(v) || mesh.degree(v) != 2) continue;
    auto h = mesh.halfedge(v);  // with v on the border: the border halfedge into v
    if (!mesh.is_border(h)) h = mesh.opposite(mesh.next(h));
    const auto inner = mesh.opposite(h);  // v -> next border vertex, inside the ear
    // (an isolated triangle, whose base is on the border too, is left alone)
    if (mesh.is_border(inner) || mesh.is_border(mesh.opposite(mesh.next(inner)))) continue;
    const auto f = mesh.face(inner);
    const auto &pa = mesh.point(mesh.source(inner)), &pb = mesh.point(mesh.target(inner)),
               &pc = mesh.point(mesh.target(mesh.next(inner)));
    if (!(triangle_gamma(pa, pb, pc) < below_gamma)) continue;
    const pipeline::Point& far_a = pb;  // the ear's base runs between v's two neighbours
    const pipeline::Point& far_b = pc;
    const double base = std::sqrt(CGAL::squared_distance(far_a, far_b));
    const double height = std::sqrt(CGAL::squared_distance(pa, pipeline::Kernel::Line_3(far_a, far_b)));
    const double along = (pa - far_a) * (far_b - far_a) / (base * base);  // v's place along the base
    if (!(height <= 0.02 * base) || !(along > 0 && along < 1)) continue;
    CGAL::Euler::remove_face(mesh.halfedge(f), mesh);  // also removes v, now isolated
    ++collapsed;
  }
  if (collapsed) mesh.collect_garbage();
  return collapsed;
}

std::size_t improve_triangles(SurfaceMesh& mesh, int rounds) {
  const auto part = mesh.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
  // First the slivers no flip or smoothing can lift (see collapse_slivers_at_cuts); the gamma
  // bound is the quality surface_mesh requires.
  collapse_slivers_at_cuts(mesh, 0.3);
  auto cut = mesh.add_property_map<SurfaceMesh::Edge_index, bool>("e:improve_cut", false).first;
  for (auto e : mesh.edges()) cut[e] = is_cut(mesh, part, e);
  const auto normal = unit_normal;
  std::size_t flipped = 0;
  for (int round = 0; round < rounds; ++round) {
    // Quality-driven flips, written here because CGAL's Delaunay flipper (inside
    // angle_and_area_smoothing) runs only with the area term, which needs Ceres. Delaunay flips
    // alone also miss the slivers along a cut: their long edge lies on the cut and cannot flip.
    std::size_t flips_this_round = 0;
    for (bool changed = true; changed;) {
      changed = false;
      for (auto e : mesh.edges()) {
        if (cut[e]) continue;
        const auto h = mesh.halfedge(e), o = mesh.opposite(h);
        const auto va = mesh.source(h), vb = mesh.target(h), vc = mesh.target(mesh.next(h)),
                   vd = mesh.target(mesh.next(o));
        if (vc == vd || mesh.halfedge(vc, vd) != SurfaceMesh::null_halfedge()) continue;  // edge cd exists
        const auto &a = mesh.point(va), &b = mesh.point(vb), &c = mesh.point(vc), &d = mesh.point(vd);
        const double before = std::min(triangle_gamma(a, b, c), triangle_gamma(b, a, d));
        const double after = std::min(triangle_gamma(c, d, b), triangle_gamma(d, c, a));
        if (after <= before + 1e-3) continue;
        // Only (nearly) flat pairs: a flip across a crease would change the surface.
        const auto n1 = normal(a, b, c), n2 = normal(b, a, d), m1 = normal(c, d, b), m2 = normal(d, c, a);
        if (n1 * n2 < coplanar_cos || m1 * m2 < coplanar_cos || m1 * (n1 + n2) <= 0 || m2 * (n1 + n2) <= 0) continue;
        CGAL::Euler::flip_edge(h, mesh);  // keeps both faces (same part) and the edge index
        changed = true;
        ++flips_this_round;
      }
    }
    flipped += flips_this_round;
    PMP::angle_and_area_smoothing(mesh.faces(), mesh,
                                  CGAL::parameters::number_of_iterations(1)
                                      .use_area_smoothing(false)
                                      .use_safety_constraints(true)
                                      .edge_is_constrained_map(cut));
    if (round > 0 && flips_this_round == 0) break;
  }
  mesh.remove_property_map(cut);
  return flipped;
}

std::vector<FitPart> build_part_model(const SurfaceMesh& mesh, const std::string& kind, bool parametrize) {
  check_parts(mesh, kind);
  const auto label = mesh.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
  std::map<int, std::vector<pipeline::FaceIndex>> faces;
  for (auto f : mesh.faces()) faces[label[f]].push_back(f);
  std::vector<FitPart> parts;
  for (auto& [l, fs] : faces) parts.push_back({fit_part_name(l, kind), l, l + 1});

  // One discrete surface per part; a node belongs to the first part that uses it (gmsh
  // re-classifies the boundary nodes onto the curves in createTopology).
  gmsh::model::add("fitted");
  std::vector<int> owner(mesh.number_of_vertices(), 0);
  for (auto& p : parts) gmsh::model::addDiscreteEntity(2, p.surface_tag);
  for (auto& p : parts) {
    std::vector<std::size_t> node_tags, tri;
    std::vector<double> coords;
    for (auto f : faces[p.label])
      for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
        tri.push_back(std::size_t(v) + 1);
        if (!owner[v]) {
          owner[v] = p.surface_tag;
          node_tags.push_back(std::size_t(v) + 1);
          const auto& q = mesh.point(v);
          coords.insert(coords.end(), {q.x(), q.y(), q.z()});
        }
      }
    gmsh::model::mesh::addNodes(2, p.surface_tag, node_tags, coords);
    gmsh::model::mesh::addElementsByType(p.surface_tag, 2, {}, tri);
  }
  try {
    gmsh::model::mesh::createTopology(true, true);
    if (parametrize) gmsh::model::mesh::createGeometry();
    else internal::number_topology_by_node_tags();  // a rebuilt model would lose the parametrization
  } catch (...) {
    throw pipeline::Error(pipeline::ErrorKind::algorithm, parametrize ? "gmsh cannot parametrize the parts (each must be a disk)"
                                                                      : "gmsh cannot build the part topology");
  }
  for (auto& p : parts) {
    gmsh::model::addPhysicalGroup(2, {p.surface_tag}, p.surface_tag);
    gmsh::model::setPhysicalName(2, p.surface_tag, p.name);
  }
  return parts;
}

std::vector<FitDeviation> fit_deviation(const SurfaceMesh& reference, const SurfaceMesh& fitted,
                                        const std::string& kind) {
  using Triangles = std::vector<pipeline::Kernel::Triangle_3>;
  using Primitive = CGAL::AABB_triangle_primitive<pipeline::Kernel, Triangles::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel, Primitive>>;
  const Triangles whole_reference = part_triangles(reference, -1), whole_fitted = part_triangles(fitted, -1);
  Tree reference_tree(whole_reference.begin(), whole_reference.end()), fitted_tree(whole_fitted.begin(), whole_fitted.end());
  reference_tree.accelerate_distance_queries();
  fitted_tree.accelerate_distance_queries();
  // The part of each triangle of the whole trees, in part_triangles' (face) order.
  auto labels_of = [](const SurfaceMesh& m) {
    const auto part = m.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
    std::vector<int> labels;
    for (auto f : m.faces()) labels.push_back(part[f]);
    return labels;
  };
  const std::vector<int> reference_labels = labels_of(reference), fitted_labels = labels_of(fitted);
  std::vector<FitDeviation> out;
  for (int label = 0; label <= (kind == "head" ? 4 : 0); ++label) {
    const Triangles a = part_triangles(reference, label), b = part_triangles(fitted, label);
    if (a.empty() && b.empty()) continue;
    FitDeviation d;
    d.name = fit_part_name(label, kind);
    if (a.empty() || b.empty())
      throw pipeline::Error(pipeline::ErrorKind::algorithm, "part " + d.name + " vanished while fitting");
    double sum2 = 0;
    auto measure = [&](const Triangles& from, const Tree& to_whole, const Triangles& whole,
                       const std::vector<int>& whole_labels, const Triangles& to_part) {
      Tree part_tree(to_part.begin(), to_part.end());
      part_tree.accelerate_distance_queries();
      for (const auto& t : from)
        for (const auto& q : {t[0], CGAL::centroid(t)}) {
          const auto hit = to_whole.closest_point_and_primitive(q);
          const double dist = std::sqrt(CGAL::squared_distance(q, hit.first));
          sum2 += dist * dist;
          if (dist > d.max_mm) d.max_mm = dist, d.max_at = q;
          ++d.samples;
          // When the nearest point of the whole surface is on this part, it is the part's nearest
          // too (the part is a subset): the second query, half of this function's time, is only
          // needed near the outlines.
          const bool on_this_part = whole_labels[std::size_t(hit.second - whole.begin())] == label;
          const double to_same_part = on_this_part ? dist : std::sqrt(part_tree.squared_distance(q));
          if (to_same_part > d.outline_shift_mm) d.outline_shift_mm = to_same_part, d.outline_shift_at = q;
        }
    };
    measure(b, reference_tree, whole_reference, reference_labels, a);
    measure(a, fitted_tree, whole_fitted, fitted_labels, b);
    d.rms_mm = std::sqrt(sum2 / d.samples);
    out.push_back(d);
  }
  return out;
}

}  // namespace scan2cad
