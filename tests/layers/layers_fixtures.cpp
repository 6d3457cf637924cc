#include "layers_fixtures.h"

#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>

#include <algorithm>

#include "pipeline/read_scan.h"

namespace PMP = CGAL::Polygon_mesh_processing;

namespace fixtures {

layering::FeModel niosh_surface(const std::string& stl, double edge_mm) {
  pipeline::SurfaceMesh m = pipeline::read_surface_mesh(stl);
  PMP::remove_degenerate_faces(m);
  m.collect_garbage();
  PMP::isotropic_remeshing(faces(m), edge_mm, m, PMP::parameters::number_of_iterations(10));
  // Remeshing leaves a few caps/needles near the capped neck; collapse/flip them away.
  PMP::experimental::remove_almost_degenerate_faces(m, -0.8, 2.5, 0.6 * edge_mm);
  m.collect_garbage();
  PMP::isotropic_remeshing(faces(m), edge_mm, m, PMP::parameters::number_of_iterations(3));
  m.collect_garbage();
  layering::FeModel out;
  for (auto v : m.vertices()) {
    const auto& p = m.point(v);
    out.nodes.emplace_back(p.x(), p.y(), p.z());
  }
  Eigen::Vector3d tip(0, 0, -1e9);
  for (const auto& p : out.nodes)
    if (std::abs(p.x()) < 5 && p.z() > tip.z()) tip = p;
  const double sellion_y = tip.y() + 38, menton_y = tip.y() - 85;
  const char* names[] = {"back_of_head", "forehead", "left_cheek", "right_cheek", "chin"};
  out.blocks.resize(5);
  for (int i = 0; i < 5; ++i) out.blocks[i] = {names[i], 2, 3, {}};
  for (auto f : m.faces()) {
    std::vector<int> ids;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (auto v : vertices_around_face(m.halfedge(f), m)) ids.push_back(int(v.idx())), c += out.nodes[v.idx()] / 3.0;
    int part = 0;
    if (c.z() > tip.z() - 75 && c.y() < sellion_y + 50 && c.y() > menton_y - 12) {
      if (c.y() > sellion_y - 10 || (std::abs(c.x()) < 16 && c.y() > tip.y() - 12 && c.z() > tip.z() - 30)) part = 1;
      else if (c.y() < menton_y + 30) part = 4;
      else part = c.x() > 0 ? 2 : 3;
    }
    out.blocks[part].conn.insert(out.blocks[part].conn.end(), ids.begin(), ids.end());
  }
  return out;
}

nlohmann::json niosh_landmarks(const layering::FeModel& head) {
  Eigen::Vector3d tip(0, 0, -1e9);
  for (const auto& p : head.nodes)
    if (std::abs(p.x()) < 5 && p.z() > tip.z()) tip = p;
  // Sellion: the deepest midline point above the nose tip; menton: the lowest midline point of the face.
  Eigen::Vector3d sel(0, 0, 1e9), men(0, 1e9, 0), trl(-1e9, 0, 0);
  for (const auto& p : head.nodes) {
    if (std::abs(p.x()) < 4 && p.y() > tip.y() + 20 && p.y() < tip.y() + 60 && p.z() > tip.z() - 40 && p.z() < sel.z()) sel = p;
    if (std::abs(p.x()) < 4 && p.z() > tip.z() - 45 && p.y() > tip.y() - 110 && p.y() < men.y()) men = p;
    if (std::abs(p.y() - (tip.y() + 10)) < 5 && p.z() < tip.z() - 100 && p.x() > trl.x()) trl = p;
  }
  auto lm = [](const Eigen::Vector3d& p) { return nlohmann::json{{"position", {p.x(), p.y(), p.z()}}, {"confidence", 1.0}}; };
  Eigen::Vector3d trr(-trl.x(), trl.y(), trl.z());
  nlohmann::json j;
  j["frame"] = "x lateral (+x = subject's left), y up, z out of the face; mm";
  j["source"] = "user";
  j["landmarks"] = {{"sellion", lm(sel)}, {"pronasale", lm(tip)}, {"menton", lm(men)},
                    {"tragion_left", lm(trl)}, {"tragion_right", lm(trr)}};
  j["measures_mm"] = {{"face_length", (sel - men).norm()}};
  return j;
}

layering::FeModel dome_respirator(double a, double b, double depth, double size) {
  // Concentric rings of 6k nodes (a hexagonal disk triangulation), mapped onto the ellipse.
  const int rings = std::max(2, int(std::ceil(std::max(a, b) / size)));
  layering::FeModel out;
  std::vector<int> first{0};
  out.nodes.emplace_back(0, 0, depth);
  for (int k = 1; k <= rings; ++k) {
    first.push_back(int(out.nodes.size()));
    for (int i = 0; i < 6 * k; ++i) {
      const double r = double(k) / rings, phi = 2 * M_PI * i / (6 * k);
      const double x = a * r * std::cos(phi), y = b * r * std::sin(phi);
      out.nodes.emplace_back(x, y, depth * (1 - r * r));
    }
  }
  layering::Block blk{"respirator_inner", 2, 3, {}};
  for (int k = 1; k <= rings; ++k) {
    const int ni = k == 1 ? 1 : 6 * (k - 1), no = 6 * k;
    auto in = [&](int i) { return k == 1 ? 0 : first[k - 1] + i % ni; };
    auto ou = [&](int j) { return first[k] + j % no; };
    int i = k == 1 ? 1 : 0, j = 0;
    while (i < ni || j < no) {
      // Advance on the ring whose next node has the smaller angle.
      const double ai = k == 1 ? 1e9 : double(i + 1) / ni, aj = double(j + 1) / no;
      if (j < no && (aj <= ai || i >= ni)) blk.conn.insert(blk.conn.end(), {in(i), ou(j), ou(j + 1)}), ++j;
      else blk.conn.insert(blk.conn.end(), {in(i), ou(j), in(i + 1)}), ++i;
    }
  }
  out.blocks.push_back(blk);
  return out;
}

}  // namespace fixtures
