#include "layering/segment.h"

#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "layering/internal/segment_cut.h"
#include "pipeline/error.h"

namespace layering {

using pipeline::FaceIndex;
using pipeline::SurfaceMesh;
using Halfedge = SurfaceMesh::Halfedge_index;
using Labels = SurfaceMesh::Property_map<FaceIndex, int>;
namespace PMP = CGAL::Polygon_mesh_processing;

const char* part_name(int label) {
  static const char* names[] = {"back_of_head", "forehead", "left_cheek", "right_cheek", "chin"};
  return label >= 0 && label < 5 ? names[label] : "unknown";
}

namespace {

double mean_edge_length(const SurfaceMesh& mesh) {
  double sum = 0;
  for (auto e : mesh.edges()) sum += PMP::edge_length(e, mesh);
  return mesh.number_of_edges() ? sum / mesh.number_of_edges() : 1.0;
}

/// Smooth maximum (log-sum-exp) of signed distances: rounds the corners of an intersection of
/// half-spaces {φ_i < 0} with a blend radius r [mm].
double smooth_max(std::initializer_list<double> phi, double r) {
  const double m = std::max(phi);
  double s = 0;
  for (double p : phi) s += std::exp((p - m) / r);
  return m + r * std::log(s);
}

/// Face components of one label; faces are adjacent across an edge.
std::vector<std::vector<FaceIndex>> components(const SurfaceMesh& mesh, const Labels& label, int l) {
  std::vector<std::vector<FaceIndex>> comps;
  std::vector<char> seen(mesh.number_of_faces(), 0);
  for (auto f : mesh.faces()) {
    if (label[f] != l || seen[f]) continue;
    comps.emplace_back();
    std::vector<FaceIndex> stack{f};
    seen[f] = 1;
    while (!stack.empty()) {
      const FaceIndex g = stack.back();
      stack.pop_back();
      comps.back().push_back(g);
      for (Halfedge h : CGAL::halfedges_around_face(mesh.halfedge(g), mesh)) {
        const FaceIndex n = mesh.face(mesh.opposite(h));
        if (n != SurfaceMesh::null_face() && label[n] == l && !seen[n]) {
          seen[n] = 1;
          stack.push_back(n);
        }
      }
    }
  }
  return comps;
}

/// Merges every component of a label other than its largest into the neighbouring label it
/// shares most edges with, until each label is one component.
void merge_islands(SurfaceMesh& mesh, Labels& label, const std::vector<int>& labels) {
  for (int pass = 0; pass < 20; ++pass) {
    bool changed = false;
    for (int l : labels) {
      auto comps = components(mesh, label, l);
      if (comps.size() < 2) continue;
      std::sort(comps.begin(), comps.end(), [](auto& a, auto& b) { return a.size() > b.size(); });
      for (std::size_t c = 1; c < comps.size(); ++c) {
        std::map<int, int> votes;
        for (FaceIndex f : comps[c])
          for (Halfedge h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh)) {
            const FaceIndex n = mesh.face(mesh.opposite(h));
            if (n != SurfaceMesh::null_face() && label[n] != l) ++votes[label[n]];
          }
        if (votes.empty()) continue;
        const int to = std::max_element(votes.begin(), votes.end(),
                                        [](auto& a, auto& b) { return a.second < b.second; })->first;
        for (FaceIndex f : comps[c]) label[f] = to;
        changed = true;
      }
    }
    if (!changed) return;
  }
}

}  // namespace

PartStats part_stats(const SurfaceMesh& mesh, int l) {
  auto found = mesh.property_map<FaceIndex, int>(pipeline::part_property);
  if (!found.second) throw pipeline::bad_input("mesh", "no face property \"f:part\" (not a segmented mesh)");
  const Labels label = found.first;
  auto in = [&](FaceIndex f) { return f != SurfaceMesh::null_face() && label[f] == l; };
  PartStats s;
  s.label = l;
  std::set<SurfaceMesh::Vertex_index> verts;
  std::size_t edges2 = 0, border = 0;  // edges counted from both sides, border edges once
  std::vector<Halfedge> boundary;
  for (auto f : mesh.faces()) {
    if (!in(f)) continue;
    ++s.faces;
    s.area_mm2 += PMP::face_area(f, mesh);
    for (Halfedge h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh)) {
      verts.insert(mesh.target(h));
      if (in(mesh.face(mesh.opposite(h)))) {
        ++edges2;
      } else {
        ++border;
        boundary.push_back(h);
      }
    }
  }
  const std::size_t edges = edges2 / 2 + border;
  s.euler = int(verts.size()) - int(edges) + int(s.faces);
  // Follow boundary loops: from a boundary halfedge, turn around its target to the next one.
  std::set<Halfedge> todo(boundary.begin(), boundary.end());
  while (!todo.empty()) {
    ++s.boundary_loops;
    Halfedge start = *todo.begin(), h = start;
    do {
      todo.erase(h);
      Halfedge n = mesh.next(h);
      while (in(mesh.face(mesh.opposite(n)))) n = mesh.next(mesh.opposite(n));
      h = n;
    } while (h != start && todo.count(h));
  }
  return s;
}

std::vector<PartStats> segment_head(SurfaceMesh& mesh, const HeadLandmarks& lm) {
  // 1. Frame quantities from the landmarks [mm].
  const double face_length = lm.sellion[1] - lm.menton[1];
  const double z_zyg = 0.5 * (lm.zygion_left[2] + lm.zygion_right[2]);
  const double z_tra = 0.5 * (lm.tragion_left[2] + lm.tragion_right[2]);
  // Coronal cut just behind the zygia, but at least a quarter of the sellion-tragion depth in
  // front of the tragia: the zygion's depth is poorly defined (NIOSH medium: hand-picked 17 mm,
  // detected 31 mm in front of the tragion), and a cheek reaching the ear root (tragus, pinna)
  // gets its 18 mm columns capped where they converge (NIOSH medium, hand-picked landmarks, 4 mm
  // surface: cheek groups -8 ... -16 % of mid-area x t, all of it within 17 mm of the tragion).
  const double z_lateral = std::max(z_zyg - 0.3 * (z_zyg - z_tra), z_tra + 0.25 * (lm.sellion[2] - z_tra));
  const double y_top = lm.sellion[1] + 0.45 * face_length;  // upper forehead
  const double gy = 0.5 * (lm.gonion_left[1] + lm.gonion_right[1]);
  const double gz = 0.5 * (lm.gonion_left[2] + lm.gonion_right[2]);
  const double gx = 0.5 * (lm.gonion_left[0] - lm.gonion_right[0]);
  // Jaw plane: contains the x axis direction, the gonia and a point under the chin where the
  // under-chin turns into the neck (about 0.12 FL below and 0.38 FL behind the menton).
  const double py = lm.menton[1] - 0.12 * face_length, pz = lm.menton[2] - 0.38 * face_length;
  double ny = -(gz - pz), nz = gy - py;
  const double nn = std::hypot(ny, nz);
  ny /= nn, nz /= nn;
  const double y_mouth = lm.menton[1] + 0.35 * face_length;
  const double blend_mm = 8.0;
  // Nose (given to the forehead part): NIOSH medium's nose protrudes over |x| < 13 mm at the
  // sellion and |x| < 20 mm at the alae, zygion breadth 142 mm.
  const double zygion_breadth = lm.zygion_left[0] - lm.zygion_right[0];
  const double nose_height = lm.sellion[1] - lm.pronasale[1];
  const double nose_root_half_width = 0.09 * zygion_breadth, nose_ala_half_width = 0.145 * zygion_breadth;
  // Lower edge: on the upper lip just below the subnasale on the midline (generated small head:
  // subnasale 0.4 nose heights below the pronasale), dipping laterally to 0.75 at the fold, below
  // the alar bases (0.55 nose heights below the pronasale, 10-14 mm off the midline): the whole underside of the nose, which faces down, goes to the
  // forehead; an 18 mm cheek column pointing up into the nose from there made wedges that the
  // layers fix loop had to thin. (0.45 instead of 0.5 left the upper lip beside the subnasale to
  // the cheeks once the corners were rounded by 6 mm: small head left cheek -5.5 %.)
  const double y_subnasale = lm.pronasale[1] - 0.5 * nose_height;
  // Lower corners rounded with 6 mm: with 3 mm the corner beside the ala (interior angle ~55 deg
  // with the dipping lower edge) was tighter than fit's 2 mm boundary edges follow, and the fitted
  // part boundary cut it by up to 1.3 mm (generated small head).
  const double nose_corner_mm = 6.0, nose_fillet_mm = 4.0;

  // 2. Fields (signed distance-like, mm); part = sign pattern.
  auto fface = mesh.add_property_map<pipeline::VertexIndex, double>("v:seg_face", 0).first;
  auto ffore = mesh.add_property_map<pipeline::VertexIndex, double>("v:seg_forehead", 0).first;
  auto fchin = mesh.add_property_map<pipeline::VertexIndex, double>("v:seg_chin", 0).first;
  auto fside = mesh.add_property_map<pipeline::VertexIndex, double>("v:seg_side", 0).first;
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    const double x = p.x(), y = p.y(), z = p.z();
    const double in_front = z_lateral - z;
    const double above_jaw = -(ny * (y - py) + nz * (z - pz));
    const double below_top = y - y_top;
    fface[v] = smooth_max({in_front, above_jaw, below_top}, blend_mm);
    // Forehead = upper-forehead band united with the nose. The nose's lateral edge is the
    // cheek-nose fold, at a half-width growing from the nasal root to the alae; its lower edge
    // lies just below the subnasale (not a landmark): 0.5 nose height below the pronasale, 0.75
    // at the alae (y_subnasale above).
    const double band = y - (lm.sellion[1] - 0.15 * face_length);
    const double t = std::clamp((lm.sellion[1] - y) / nose_height, 0.0, 1.0);
    const double half_width = nose_root_half_width + t * (nose_ala_half_width - nose_root_half_width);
    const double lateral = std::min(1.0, (x * x) / (nose_ala_half_width * nose_ala_half_width));
    const double y_nose_bottom = y_subnasale - 0.25 * nose_height * lateral;
    const double nose = -smooth_max({std::abs(x) - half_width, y_nose_bottom - y}, nose_corner_mm);
    ffore[v] = smooth_max({band, nose}, nose_fillet_mm);
    fchin[v] = y - (y_mouth - (y_mouth - gy) * (x / gx) * (x / gx));
    fside[v] = x;
  }
  std::vector<internal::Field> fields{fface, ffore, fchin, fside};
  const double snap = 0.1 * mean_edge_length(mesh);
  for (std::size_t i = 0; i < fields.size(); ++i) internal::cut_at_zero(mesh, fields, i, snap);

  // 3. Label each face from the signs of the fields (a face has no mixed signs after cutting).
  Labels label = mesh.add_property_map<FaceIndex, int>(pipeline::part_property, 0).first;
  for (auto f : mesh.faces()) {
    double s[4] = {0, 0, 0, 0};
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      for (int i = 0; i < 4; ++i) s[i] += fields[i][v];
    if (s[0] >= 0) label[f] = back_of_head;
    else if (s[1] > 0) label[f] = forehead;
    else if (s[2] < 0) label[f] = chin;
    else label[f] = s[3] > 0 ? left_cheek : right_cheek;
  }
  for (auto& f : fields) mesh.remove_property_map(f);

  // 4. Islands merged; each label one connected piece.
  merge_islands(mesh, label, {forehead, left_cheek, right_cheek, chin, back_of_head});
  std::vector<PartStats> stats;
  for (int l = 0; l < 5; ++l) {
    stats.push_back(part_stats(mesh, l));
    if (stats.back().faces == 0)
      throw pipeline::Error(pipeline::ErrorKind::algorithm,
                            std::string("part ") + part_name(l) + " is empty: are the landmarks on this head?");
  }
  return stats;
}

void require_respirator_sheet(const PartStats& st) {
  // A capped cup (its rim closed) kept no rim, and went on to fail in layers with a fold "on the
  // skin"; a surface whose two walls reconstruct had merged into one (a respirator scan with its
  // own normals) kept 57 handles, and fit crashed in CGAL's remeshing on it (sweep K).
  if (st.boundary_loops == 0)
    throw pipeline::bad_input("respirator", "its inner face is closed (no rim): a respirator is open toward the face; "
                                            "is its rim capped, or is it not a respirator?");
  if (const int handles = (2 - st.euler - st.boundary_loops) / 2; handles > 0)
    throw pipeline::bad_input("respirator", "its inner face has " + std::to_string(handles) + " handle" +
                                                (handles > 1 ? "s" : "") + " (Euler characteristic " + std::to_string(st.euler) +
                                                ", " + std::to_string(st.boundary_loops) +
                                                " rim(s)), not a sheet: a disc or a ring was expected; were its two walls "
                                                "merged into one (reconstruct's log: a thin shell is named there)?");
}

PartStats segment_respirator(SurfaceMesh& mesh, RespiratorSegmentInfo* info) {
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel, CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>>>;
  if (mesh.number_of_faces() == 0) throw pipeline::bad_input("respirator", "no faces");
  mesh.collect_garbage();
  // 0. A closed shell is oriented outward (normals out of the material) so that "toward the
  //    face" means the same thing on every sheet.
  if (CGAL::is_closed(mesh)) PMP::orient_to_bound_a_volume(mesh);
  const std::size_t nf = mesh.number_of_faces();
  std::vector<pipeline::Vector> normal(nf);
  std::vector<pipeline::Point> centre(nf);
  for (auto f : mesh.faces()) {
    normal[f] = PMP::compute_face_normal(f, mesh);
    const auto h = mesh.halfedge(f);
    centre[f] = CGAL::centroid(mesh.point(mesh.source(h)), mesh.point(mesh.target(h)), mesh.point(mesh.target(mesh.next(h))));
  }
  // 1. How much a face looks toward the face side (-z): breaks ties between the sheets and
  //    orients a single open sheet.
  std::vector<double> toward_face(nf);
  for (auto f : mesh.faces()) toward_face[f] = -normal[f].z();
  // 2. Wall partner of each face: the first face hit by a ray from its centre into the material
  //    (-normal). On the two sheets of a thin shell it is the opposite sheet at about the wall
  //    thickness; on the rim strip joining them (and on an open sheet) the ray runs along the
  //    wall or escapes, so no partner is found near. (Hand-written pairing: CGAL has no thin-shell
  //    sheet classification; the ray queries are CGAL's AABB tree.)
  Tree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.accelerate_distance_queries();
  std::vector<double> hit_mm(nf, std::numeric_limits<double>::infinity());
  std::vector<FaceIndex> partner(nf, SurfaceMesh::null_face());
  for (auto f : mesh.faces()) {
    std::set<FaceIndex> near{f};  // the face and its vertex neighbours (grazing hits at distance ~0)
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      for (auto g : CGAL::faces_around_target(mesh.halfedge(v), mesh)) near.insert(g);
    const pipeline::Kernel::Ray_3 ray(centre[f], -normal[f]);
    const auto hit = tree.first_intersection(ray, [&](FaceIndex g) { return near.count(g) > 0; });
    if (!hit) continue;
    if (const pipeline::Point* p = boost::get<pipeline::Point>(&hit->first)) {
      hit_mm[f] = std::sqrt(CGAL::squared_distance(*p, centre[f]));
      partner[f] = hit->second;
    }
  }
  // Wall thickness: median partner distance (most faces lie on the two sheets).
  std::vector<double> finite;
  for (double t : hit_mm)
    if (std::isfinite(t)) finite.push_back(t);
  double wall_mm = 0;
  if (!finite.empty()) {
    std::nth_element(finite.begin(), finite.begin() + finite.size() / 2, finite.end());
    wall_mm = finite[finite.size() / 2];
  }
  // Paired: the hit face faces the other way (within 45 deg of opposite; a ray along a rim strip
  // meets the sheets at a grazing angle) and is not far beyond the typical wall (real parts vary
  // in thickness: the Flex face seal's wall is 0.85-3 mm).
  const double pair_limit_mm = 8 * wall_mm;
  std::vector<char> is_paired(nf, 0);
  std::size_t paired = 0;
  for (auto f : mesh.faces())
    if (hit_mm[f] <= pair_limit_mm && normal[f] * normal[partner[f]] < -0.7) is_paired[f] = 1, ++paired;
  // A thin shell has most faces paired; otherwise the input is taken as a single open sheet.
  const bool thin_shell = wall_mm > 0 && paired > nf / 2;
  // A closed solid pairs its faces too, across its whole depth: a head given as a respirator
  // (NIOSH medium: 152 mm) would be cut in half and layered as a 150 mm "wall". Respirator walls
  // are a few mm (the Flex face seal 0.85-3 mm; the generated cups are single sheets).
  constexpr double max_wall_mm = 20;
  if (thin_shell && wall_mm > max_wall_mm)
    throw pipeline::bad_input("respirator", "its two sheets are " + std::to_string(int(std::lround(wall_mm))) +
                                                " mm apart, more than a respirator's wall of a few mm: is it a head?");
  // 3. Inner faces. On a thin shell: of a face and its partner, the one that faces the cavity,
  //    i.e. sees more of the shell around it (share of 24 rays spread over the hemisphere of its
  //    normal that hit the shell): the inside of a cup, funnel or tray is enclosed, the outside
  //    is not. A plain -z test fails where the wall is parallel to z and on parts that are not
  //    cups (the real Conforming invert is a tray open toward +z). Near-ties (< 0.1 apart, e.g. a
  //    flat flange) go to the face looking toward -z. On a single sheet: every face, the sheet
  //    oriented toward -z first.
  Labels label = mesh.add_property_map<FaceIndex, int>(pipeline::part_property, 1).first;
  for (auto f : mesh.faces()) label[f] = 1;  // an input that is already labelled starts afresh
  if (thin_shell) {
    std::vector<double> enclosed(nf, -1.0);
    auto enclosure = [&](FaceIndex f) {
      if (enclosed[f] >= 0) return enclosed[f];
      const auto& n = normal[f];
      const pipeline::Vector t1 = std::abs(n.x()) < 0.9 ? CGAL::cross_product(n, pipeline::Vector(1, 0, 0))
                                                        : CGAL::cross_product(n, pipeline::Vector(0, 1, 0));
      const pipeline::Vector u = t1 / std::sqrt(t1.squared_length()), w = CGAL::cross_product(n, u);
      const pipeline::Point origin = centre[f] + 1e-3 * wall_mm * n;
      const int rays = 24;
      int hits = 0;
      for (int k = 0; k < rays; ++k) {
        // Fibonacci spiral over the hemisphere, cos(angle to the normal) from 0.96 down to 0.17.
        const double cz = 0.96 - 0.79 * (k + 0.5) / rays, sz = std::sqrt(1 - cz * cz);
        const double phi = k * 2.399963229728653;  // golden angle [rad]
        const pipeline::Vector d = cz * n + sz * (std::cos(phi) * u + std::sin(phi) * w);
        hits += tree.do_intersect(pipeline::Kernel::Ray_3(origin, d));
      }
      return enclosed[f] = double(hits) / rays;
    };
    for (auto f : mesh.faces()) {
      if (!is_paired[f]) continue;
      const double here = enclosure(f), there = enclosure(partner[f]);
      if (std::abs(here - there) >= 0.1 ? here > there : toward_face[f] > toward_face[partner[f]])
        label[f] = respirator_inner;
    }
  } else {
    double s = 0;
    for (auto f : mesh.faces()) s += toward_face[f] * PMP::face_area(f, mesh);
    if (s < 0) PMP::reverse_face_orientations(mesh);
    for (auto f : mesh.faces()) label[f] = respirator_inner;
  }
  // 4. One piece: islands of either label merged into the other; then the rim made smooth:
  //    inner faces with two edges on the rim (teeth) dropped, outer faces with two edges against
  //    the inner face (notches) taken in.
  merge_islands(mesh, label, {respirator_inner, 1});
  auto inner = [&](FaceIndex f) { return f != SurfaceMesh::null_face() && label[f] == respirator_inner; };
  for (int pass = 0; pass < 5; ++pass) {
    std::vector<FaceIndex> flip;
    for (auto f : mesh.faces()) {
      int against_inner = 0;
      for (Halfedge h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh))
        against_inner += inner(mesh.face(mesh.opposite(h)));
      if (inner(f) ? against_inner <= 1 : against_inner >= 2) flip.push_back(f);
    }
    if (flip.empty()) break;
    for (auto f : flip) label[f] = inner(f) ? 1 : respirator_inner;
  }
  merge_islands(mesh, label, {respirator_inner, 1});
  // 5. Drop everything but the inner face.
  std::vector<FaceIndex> drop;
  for (auto f : mesh.faces())
    if (label[f] != respirator_inner) drop.push_back(f);
  for (auto f : drop) CGAL::Euler::remove_face(mesh.halfedge(f), mesh);
  mesh.collect_garbage();
  if (mesh.number_of_faces() == 0)
    throw pipeline::Error(pipeline::ErrorKind::algorithm,
                          "no inner face found: is the respirator aligned (concave side toward -z)?");
  if (info) {
    info->thin_shell = thin_shell;
    info->wall_mm = wall_mm;
    info->paired_fraction = double(paired) / double(nf);
    info->faces_dropped = drop.size();
  }
  // 6. A sheet: a disc (a cup) or a ring (a frame with a port hole).
  const PartStats st = part_stats(mesh, respirator_inner);
  require_respirator_sheet(st);
  return st;
}

}  // namespace layering
