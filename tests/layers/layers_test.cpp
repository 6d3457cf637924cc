#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <utility>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <nlohmann/json.hpp>

#include "layering/internal/layers_columns.h"
#include "layering/internal/segment_landmarks.h"
#include "layering/layers.h"
#include "layering/segment.h"
#include "check_head_layers.h"
#include "layers_fixtures.h"
#include "pipeline/atomic_write.h"
#include "pipeline/error.h"
#include "pipeline/read_scan.h"
#include "../bad_input_message.h"
#include "../run_command.h"
#include "../scratch_dir.h"

namespace {

const std::string kMaterials = std::string(SOURCE_DIR) + "/data/materials.json";
const std::string kNioshMedium = std::string(SHARED_DATA_DIR) + "/headforms/NIOSH_medium_20k.stl";

// NIOSH medium remeshed to edge_mm (the fixture's surface) with the parts of segment_head (the
// hand-picked landmarks of tests/segment): each remeshed triangle takes the part of the nearest
// face of the segmented 20k-triangle headform. Part boundaries follow the remeshed edges (a
// staircase at edge_mm), not segment's smooth curves, which fit + surface_mesh would give.
layering::FeModel niosh_segmented_surface(double edge_mm) {
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<pipeline::Kernel,
                                                 CGAL::AABB_face_graph_triangle_primitive<pipeline::SurfaceMesh>>>;
  layering::FeModel surface = fixtures::niosh_surface(kNioshMedium, edge_mm);
  pipeline::SurfaceMesh dense = pipeline::read_surface_mesh(kNioshMedium);
  layering::segment_head(dense, layering::internal::read_segment_landmarks(
                                    std::string(SOURCE_DIR) + "/tests/segment/niosh_medium_landmarks.json"));
  const auto part = dense.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
  Tree tree(faces(dense).first, faces(dense).second, dense);
  tree.accelerate_distance_queries();
  std::vector<layering::Block> blocks;
  for (int l = 0; l < 5; ++l) blocks.push_back({layering::part_name(l), 2, 3, {}});
  for (const auto& b : surface.blocks)
    for (std::size_t e = 0; e < b.size(); ++e) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) c += surface.nodes[b.conn[3 * e + k]] / 3.0;
      const auto hit = tree.closest_point_and_primitive(pipeline::Point(c.x(), c.y(), c.z()));
      auto& to = blocks[part[hit.second]].conn;
      to.insert(to.end(), b.conn.begin() + 3 * e, b.conn.begin() + 3 * e + 3);
    }
  surface.blocks = blocks;
  return surface;
}

// Layers a real NIOSH head and checks every property issue 4 asks for.
void check_head(const layering::FeModel& surface, const std::string& stl) {
  layering::LayerReport rep;
  const layering::FeModel m =
      layering::build_layers(surface, layering::read_stacks(kMaterials, "head"), layering::LayerOptions{}, &rep);
  layers_test::expect_valid_head_layers(m, rep, stl);
}

}  // namespace

TEST(wedge_scaled_jacobian, equilateral_prism_scores_one_and_inverted_is_negative) {
  const double h = std::sqrt(3.0) / 2;
  Eigen::Vector3d p[6] = {{0, 0, 0}, {1, 0, 0}, {0.5, h, 0}, {0, 0, 1}, {1, 0, 1}, {0.5, h, 1}};
  EXPECT_NEAR(layering::wedge_scaled_jacobian(p), 1.0, 1e-12);
  EXPECT_NEAR(layering::wedge_volume(p), h / 2, 1e-12);
  std::swap(p[1], p[2]);
  std::swap(p[4], p[5]);
  EXPECT_LT(layering::wedge_scaled_jacobian(p), 0.0);
  EXPECT_LT(layering::wedge_volume(p), 0.0);
}

TEST(build_layers, niosh_medium_wedges_valid_and_volumes_within_5_percent) {
  check_head(fixtures::niosh_surface(kNioshMedium, 4.0), kNioshMedium + " (box parts)");
}

TEST(build_layers, niosh_medium_segment_parts_wedges_valid_and_volumes_within_5_percent) {
  // The parts of segment_head: the nose (to just below the subnasale) belongs to the forehead's
  // 7 mm stack; when the cheeks held it, their 18 mm columns were thinned under the nose and the
  // cheek groups missed mid-area x t by 8-17 % on the chain heads.
  check_head(niosh_segmented_surface(4.0), kNioshMedium + " (segment_head parts)");
}

// A thinned column's taper, on a flat patch (forehead x < 0: 7 mm stack; left cheek x > 0: 18 mm)
// of near-equilateral triangles at three edge lengths. One cheek column and one column on the part
// boundary are set to half depth (what a convergence cap or the fix loop does under the nose); the
// depth limit must taper them off smoothly but within a fixed width in mm: an 18 mm column within
// 20 mm, and the forehead's shallow columns within 10 mm. The old limit (0.15 of the scale per
// edge) spread every thinned spot over ~4 edges of every part, 26-28 mm at 6.4-7 mm edges and
// forehead columns alike: that cost the generated shortwide head's left cheek 5.1 % of its
// volume (issue 4 asks <= 5 %). With it this test fails at 6.4 and 7 mm (taper too wide) and at
// 3.2 mm (too steep: 0.84 mm per mm on the cheek, the same scale jump over a shorter edge).
TEST(layers_columns, thinned_column_tapers_within_a_fixed_width_at_any_edge_length) {
  for (double h : {3.2, 6.4, 7.0}) {
    SCOPED_TRACE("edge " + std::to_string(h) + " mm");
    layering::internal::Input in;
    const double row = h * std::sqrt(3.0) / 2;
    const int nx = int(45 / h), ny = int(35 / row);
    std::map<std::pair<int, int>, int> id;
    for (int j = -ny; j <= ny; ++j)
      for (int i = -nx; i <= nx; ++i) {
        id[{i, j}] = int(in.nodes.size());
        in.nodes.emplace_back(i * h + (j % 2 ? 0.5 * h : 0.0), j * row, 0.0);
      }
    const auto stacks = layering::read_stacks(kMaterials, "head");
    in.parts = {{"forehead", {}, stacks.at("forehead")}, {"left_cheek", {}, stacks.at("left_cheek")}};
    auto add = [&](int a, int b, int c) {
      const double cx = (in.nodes[a].x() + in.nodes[b].x() + in.nodes[c].x()) / 3;
      in.parts[cx < 0 ? 0 : 1].tris.push_back({a, b, c});
    };
    for (int j = -ny; j < ny; ++j)
      for (int i = -nx; i < nx; ++i) {
        const int a = id[{i, j}], b = id[{i + 1, j}], c = id[{i, j + 1}], d = id[{i + 1, j + 1}];
        if (j % 2 == 0) add(a, b, c), add(b, d, c);  // even rows: the row above is shifted +h/2
        else add(a, d, c), add(a, b, d);
      }
    layering::internal::Columns col = layering::internal::make_columns(in, layering::LayerOptions{});
    ASSERT_DOUBLE_EQ(col.min_scale(), 1.0);  // a flat patch needs no thinning
    std::vector<char> in_cheek(in.nodes.size(), 0);
    for (const auto& t : in.parts[1].tris)
      for (int v : t) in_cheek[v] = 1;
    const auto nbr = layering::internal::skin_neighbours(in);
    const int cheek_spot = id[{int(std::lround(25 / h)), 0}], boundary_spot = id[{0, 0}];
    ASSERT_TRUE(in_cheek[boundary_spot] && in_cheek[cheek_spot]);
    col.scale[cheek_spot] = col.scale[boundary_spot] = 0.5;
    layering::internal::limit_depth_gradient(nbr, in.nodes, col);
    auto depth = [&](int i) { return col.scale[i] * col.levels[col.max_level[i]]; };
    double worst_slope = 0;
    std::size_t checked_cheek = 0, checked_forehead = 0;
    for (int i : col.skin) {
      for (int j : nbr[i])
        if (col.max_level[i] == col.max_level[j])
          worst_slope = std::max(worst_slope, std::abs(depth(i) - depth(j)) / (in.nodes[i] - in.nodes[j]).norm());
      const double r = std::min((in.nodes[i] - in.nodes[cheek_spot]).norm(), (in.nodes[i] - in.nodes[boundary_spot]).norm());
      if (in_cheek[i] && r >= 20) {
        EXPECT_DOUBLE_EQ(col.scale[i], 1.0) << "cheek column " << r << " mm away";
        ++checked_cheek;
      }
      if (!in_cheek[i] && r >= 10) {
        EXPECT_DOUBLE_EQ(col.scale[i], 1.0) << "forehead column " << r << " mm away";
        ++checked_forehead;
      }
    }
    EXPECT_GT(checked_cheek, 10u);
    EXPECT_GT(checked_forehead, 10u);
    // Still a taper, not a step: along every edge of one stack the depth changes by at most the
    // limit's slope (31 deg), and the spots' neighbours are thinned too.
    EXPECT_LE(worst_slope, layering::internal::kMaxDepthSlope + 1e-9);
    EXPECT_LT(col.scale[nbr[cheek_spot][0]], 1.0);
    EXPECT_DOUBLE_EQ(col.scale[cheek_spot], 0.5);
  }
}

// A shell (a group without layers, like back_of_head) that cuts through itself is no model: the
// fix loop cannot mend it, since no column moves a shell, and layers must refuse it, not write it
// with exit 0 and "0 intersecting faces". A flat forehead patch with two crossing triangles as
// its back_of_head, 50 mm off on the layers' side; the same without the crossing layers cleanly.
TEST(build_layers, a_self_intersecting_shell_is_refused) {
  layering::FeModel surface;
  layering::Block forehead{"forehead", 2, 3, {}}, back{"back_of_head", 2, 3, {}};
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i) surface.nodes.emplace_back(4.0 * i, 4.0 * j, 0.0);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const int a = 5 * j + i, b = a + 1, c = a + 5, d = a + 6;
      forehead.conn.insert(forehead.conn.end(), {a, b, d, a, d, c});
    }
  const int n = int(surface.nodes.size());
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(3, 8, 50), Eigen::Vector3d(13, 8, 50), Eigen::Vector3d(8, 8, 60),
                                   Eigen::Vector3d(8, 3, 52), Eigen::Vector3d(8, 13, 52), Eigen::Vector3d(8, 8, 58)})
    surface.nodes.push_back(p);
  back.conn = {n, n + 1, n + 2, n + 3, n + 4, n + 5};  // two triangles crossing along x = y = 8
  surface.blocks = {forehead, back};
  const auto stacks = layering::read_stacks(kMaterials, "head");
  const std::map<std::string, layering::Stack> forehead_only = {{"forehead", stacks.at("forehead")}};
  EXPECT_EQ(error_message(pipeline::ErrorKind::algorithm, [&] { layering::build_layers(surface, forehead_only, {}, nullptr); }),
            "shell triangles (of the groups without layers) intersect in 1 pairs: a self-intersecting "
            "surface (repair it)");
  surface.blocks[1].conn = {n, n + 1, n + 2};
  layering::LayerReport report;
  const auto layered = layering::build_layers(surface, forehead_only, {}, &report);
  EXPECT_EQ(report.intersecting_pairs, 0u);
  EXPECT_EQ(layering::count_intersecting_faces(layered), 0u);
}

TEST(build_layers, respirator_dome_has_seal_and_outer_layers) {
  layering::LayerOptions opt;
  opt.kind = "respirator";
  layering::LayerReport rep;
  const layering::FeModel m = layering::build_layers(fixtures::dome_respirator(), layering::read_stacks(kMaterials, "respirator"), opt, &rep);
  ASSERT_NE(m.find("respirator_seal"), nullptr);
  ASSERT_NE(m.find("respirator_outer"), nullptr);
  ASSERT_NE(m.find("respirator_rim"), nullptr);
  EXPECT_GE(rep.min_scaled_jacobian, 0.2);
  EXPECT_EQ(layering::count_intersecting_faces(m), 0u);
  // Offsetting away from the face (+z) on the cup: a wedge's bottom (deeper) nodes lie above its top.
  const auto& seal = *m.find("respirator_seal");
  EXPECT_GT(m.nodes[seal.conn[0]].z() - m.nodes[seal.conn[3]].z(), 0.5);
  ASSERT_EQ(rep.volumes.size(), 2u);  // the respirator's two layers (data/materials.json)
  for (const auto& v : rep.volumes) EXPECT_NEAR(v.volume / v.mid_area_volume, 1.0, 0.05) << v.group;
}

// --elements-per-tissue reaches the mesh: three element layers through the seal, one through the
// outer layer, give three times the seal's wedges and the outer layer's count unchanged (the
// option was tested only as parsed text; ignoring it passed: sweep L).
TEST(build_layers, elements_per_tissue_divides_that_tissue_only) {
  const auto stacks = layering::read_stacks(kMaterials, "respirator");
  layering::LayerOptions one;
  one.kind = "respirator";
  layering::LayerOptions three = one;
  three.elements_per_tissue = layering::parse_elements_per_tissue("seal_layer=3", stacks);
  const layering::FeModel a = layering::build_layers(fixtures::dome_respirator(), stacks, one, nullptr);
  const layering::FeModel b = layering::build_layers(fixtures::dome_respirator(), stacks, three, nullptr);
  for (const char* g : {"respirator_seal", "respirator_outer"}) {
    ASSERT_NE(a.find(g), nullptr) << g;
    ASSERT_NE(b.find(g), nullptr) << g;
  }
  const auto wedges = [](const layering::FeModel& m, const char* g) { return m.find(g)->size(); };
  ASSERT_GT(wedges(a, "respirator_seal"), 0u);
  EXPECT_EQ(wedges(b, "respirator_seal"), 3 * wedges(a, "respirator_seal"));
  EXPECT_EQ(wedges(b, "respirator_outer"), wedges(a, "respirator_outer"));
}

TEST(write_fe_model, round_trip_and_opens_in_meshio) {
  layering::LayerOptions opt;
  opt.kind = "respirator";
  const layering::FeModel m = layering::build_layers(fixtures::dome_respirator(), layering::read_stacks(kMaterials, "respirator"), opt, nullptr);
  const std::string path = (scratch_dir() / "roundtrip.msh").string();
  layering::write_fe_model(m, path);
  const layering::FeModel r = layering::read_fe_model(path);
  ASSERT_EQ(r.nodes.size(), m.nodes.size());
  double moved_mm = 0;  // gmsh writes 16 significant digits: ~1e-14 mm on a 100 mm model
  for (std::size_t i = 0; i < m.nodes.size(); ++i) moved_mm = std::max(moved_mm, (r.nodes[i] - m.nodes[i]).norm());
  EXPECT_LT(moved_mm, 1e-9);
  for (const auto& b : m.blocks) {
    const auto* rb = r.find(b.name);
    ASSERT_NE(rb, nullptr) << b.name;
    EXPECT_EQ(rb->dim, b.dim) << b.name;
    EXPECT_EQ(rb->conn, b.conn) << b.name;
  }
  const std::string cmd = std::string(SYSTEM_PYTHON) + " -c \"import meshio; m = meshio.read('" + path +
                          "'); assert sum(len(c.data) for c in m.cells if c.type == 'wedge') > 0\"";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
}

TEST(layers_cli, missing_input_exits_2_without_output) {
  const std::string out = (scratch_dir() / "none.msh").string();
  std::filesystem::remove(out);
  const std::string cmd = std::string(BIN_DIR) + "/layers --in /nonexistent.msh --materials " + kMaterials +
                          " --out " + out + " 2>/dev/null";
  EXPECT_EQ(run_command(cmd), 2);
  EXPECT_FALSE(std::filesystem::exists(out));
}

// gmsh picks the format from the ending: `--out x.txt` failed after the layering with "Unknown
// output file format" (exit 3), naming no file. Now a usage error before the input is read.
TEST(layers_cli, out_not_ending_in_msh_is_a_usage_error_naming_it) {
  const std::string out = (scratch_dir() / "layers.txt").string(), log = (scratch_dir() / "ext_log.txt").string();
  const std::string cmd = std::string(BIN_DIR) + "/layers --in /nonexistent.msh --materials " + kMaterials +
                          " --out " + out + " 2> " + log;
  EXPECT_EQ(run_command(cmd), 1);
  std::ifstream in(log);
  std::string first_error;
  for (std::string line; std::getline(in, line) && first_error.empty();)
    if (line.find("options:") == std::string::npos) first_error = line;
  EXPECT_EQ(first_error, "layers: --out: '" + out + "' must end in .msh (see 'layers --help')");
  EXPECT_FALSE(std::filesystem::exists(out));
}

// gmsh throws its errors as std::string, which the reader once let through as an internal error
// (exit 3, "Error loading ..."); an empty file read as a mesh without groups. gmsh reads a NaN
// coordinate without complaint; layers then failed after 60 thinning passes, and straps and
// assemble (same reader) died of a floating-point trap in CGAL's exact predicates.
TEST(layers_cli, empty_truncated_or_nan_msh_exits_2_with_one_line_naming_it) {
  const std::filesystem::path dir = scratch_dir() / "bad";
  std::filesystem::create_directories(dir);
  const std::string triangle_with_nan_node =
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"forehead\"\n$EndPhysicalNames\n"
      "$Entities\n0 0 1 0\n1 0 0 0 1 1 0 1 1 0\n$EndEntities\n"
      "$Nodes\n1 3 1 3\n2 1 0 3\n1\n2\n3\n0 0 0\n10 nan 0\n0 10 0\n$EndNodes\n"
      "$Elements\n1 1 1 1\n2 1 2 1\n1 1 2 3\n$EndElements\n";
  // Nodes of a head's size (require_mm checks the extent) and no elements: gmsh also reads a
  // $Nodes section without its $EndNodes this way, and layers wrote an empty model with exit 0.
  const std::string head_sized_nodes_only =
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"forehead\"\n$EndPhysicalNames\n"
      "$Entities\n0 0 1 0\n1 0 0 0 1 1 0 1 1 0\n$EndEntities\n"
      "$Nodes\n1 3 1 3\n2 1 0 3\n1\n2\n3\n0 0 0\n200 0 0\n0 200 0\n$EndNodes\n";
  std::string without_end_nodes = triangle_with_nan_node;
  without_end_nodes.erase(without_end_nodes.find("$EndNodes\n"), 10);
  const std::tuple<std::string, std::string, std::string> bad[] = {
      {"empty.msh", "", "file is empty"},
      // (its only group, forehead, has no triangles; the stacks' chin is the first group missing)
      {"no_elements.msh", head_sized_nodes_only, "no triangle group chin, which "},
      {"no_end_nodes.msh", without_end_nodes, "section $Nodes (line 12) is not closed by $EndNodes"},
      {"truncated.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n",
       "section $Nodes (line 4) is not closed by $EndNodes (truncated file?)"},
      {"nan.msh", triangle_with_nan_node, "node 2 has a non-finite coordinate"},
  };
  for (const auto& [name, text, words] : bad) {
    std::ofstream(dir / name) << text;
    const std::string out = (dir / (name + ".layers.msh")).string(), log = (dir / "log.txt").string();
    const std::string cmd = std::string(BIN_DIR) + "/layers --in " + (dir / name).string() + " --materials " +
                            kMaterials + " --out " + out + " > /dev/null 2> " + log;
    EXPECT_EQ(run_command(cmd), 2) << name;
    std::ifstream in(log);
    std::string line, last;
    int lines = 0;
    while (std::getline(in, line))
      if (line.find("options:") == std::string::npos) ++lines, last = line;  // the resolved-options log line
    EXPECT_EQ(lines, 1) << last;
    EXPECT_NE(last.find(name + ": " + words), std::string::npos) << last;
    EXPECT_FALSE(std::filesystem::exists(out)) << name;
  }
}

// Layer thicknesses: none, negative, and in the wrong unit (a 1 m skin was layered as columns
// thinned a millionfold) are bad input naming the file and the part.
TEST(read_stacks, rejects_absurd_layer_thicknesses) {
  const nlohmann::json good = nlohmann::json::parse(pipeline::read_text(kMaterials));
  const std::filesystem::path path = scratch_dir() / "read_stacks.json";
  for (const double mm : {0.0, -3.0, 1000.0, 1e-9, 0.05}) {  // 1e-9 mm was layered as an empty group
    nlohmann::json bad = good;
    bad["head_layers_mm"]["forehead"][0][1] = mm;
    pipeline::write_text_atomic(path.string(), bad.dump());
    const std::string message = bad_input_message([&] { layering::read_stacks(path.string(), "head"); }, path);
    EXPECT_EQ(message.rfind("head_layers_mm.forehead: bad layer", 0), 0u) << mm << " mm: " << message;
  }
  // 1000 layers of 0.01 mm ran out of memory; ten 0.1 mm layers are allowed (each of its own
  // material, soft ones on bone)
  for (const std::size_t n : {10u, 11u}) {
    nlohmann::json stack = good;
    stack["head_layers_mm"]["forehead"] = nlohmann::json::array();
    for (std::size_t k = 0; k + 1 < n; ++k) {
      const std::string name = "tissue" + std::to_string(k);
      stack["materials"][name] = good["materials"]["skin"];
      stack["head_layers_mm"]["forehead"].push_back({name, 0.1});
    }
    stack["head_layers_mm"]["forehead"].push_back({"bone", 0.1});
    pipeline::write_text_atomic(path.string(), stack.dump());
    EXPECT_EQ(bad_input_message([&] { layering::read_stacks(path.string(), "head"); }, path),
              n == 10 ? "no error" : "head_layers_mm.forehead: 11 layers, expected at most 10");
  }
  EXPECT_NO_THROW(layering::read_stacks(kMaterials, "head"));
}

// Stacks that make no model: a material twice (its layer's group left unnamed, exit 0), a face part
// without bone under it or with the bone above soft tissue, and a stack for the rigid back of the
// head (22,913 wedges no deck fixed) all passed layers and assemble.
TEST(read_stacks, refuses_a_material_twice_no_bone_innermost_and_a_back_of_head_stack) {
  const nlohmann::json good = nlohmann::json::parse(pipeline::read_text(kMaterials));
  const std::filesystem::path path = scratch_dir() / "read_stacks_order.json";
  const auto message = [&](const std::string& part, const nlohmann::json& stack, const std::string& kind = "head") {
    nlohmann::json edited = good;
    (kind == "head" ? edited["head_layers_mm"][part] : edited["respirator_layers_mm"]) = stack;
    pipeline::write_text_atomic(path.string(), edited.dump());
    return bad_input_message([&] { layering::read_stacks(path.string(), kind); }, path);
  };
  using J = nlohmann::json;
  EXPECT_EQ(message("forehead", J::parse(R"([["skin", 5], ["skin", 2], ["bone", 2]])")),
            "head_layers_mm.forehead: material 'skin' twice in one stack");
  EXPECT_EQ(message("chin", J::parse(R"([["skin", 3], ["bone", 2], ["bone", 2]])")),
            "head_layers_mm.chin: material 'bone' twice in one stack");
  EXPECT_EQ(message("forehead", J::parse(R"([["skin", 5], ["fat", 2]])")),
            "head_layers_mm.forehead: the innermost layer, 'fat', is not rigid: a face part's tissue rests on bone");
  EXPECT_EQ(message("forehead", J::parse(R"([["bone", 2], ["skin", 5], ["back_of_head", 1]])")),
            "head_layers_mm.forehead: 'bone' is rigid but not the innermost layer (layers go from the skin inward)");
  EXPECT_EQ(message("back_of_head", J::parse(R"([["skin", 3], ["bone", 2]])")),
            "head_layers_mm.back_of_head: the back of the head is a rigid shell and takes no stack");
  EXPECT_EQ(message("forehead", J::parse(R"([["skin", 4], ["muscle", 2], ["bone", 2]])")), "no error");
  // a respirator has no bone: its soft layers stand alone
  EXPECT_EQ(message("", J::parse(R"([["seal_layer", 1], ["outer_layer", 2]])"), "respirator"), "no error");
  EXPECT_EQ(message("", J::parse(R"([["seal_layer", 1], ["seal_layer", 2]])"), "respirator"),
            "respirator_layers_mm: material 'seal_layer' twice in one stack");
}

// An edited surface: a duplicated triangle was layered as coincident wedges, a triangle with a
// repeated node copied into the model, both with exit 0.
TEST(require_clean_triangles, names_a_repeated_node_a_zero_area_or_a_repeated_triangle) {
  layering::FeModel m;
  m.nodes = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {10, 10, 0}, {20, 20, 0}};
  m.blocks.push_back(layering::Block{"respirator_inner", 2, 3, {0, 1, 2, 1, 3, 2}});
  m.blocks.push_back(layering::Block{"back_of_head", 2, 3, {}});
  auto message = [&](std::vector<int> back) {
    m.blocks[1].conn = std::move(back);
    return bad_input_message([&] { layering::require_clean_triangles(m, "s.msh"); }, "s.msh");
  };
  EXPECT_EQ(message({}), "no error");
  EXPECT_EQ(message({1, 4, 3}), "no error");
  // Named by position and rank, counted from 1: the file's element tags are not what the model keeps.
  EXPECT_EQ(message({3, 3, 4}), "back_of_head's triangle 1 of 1, at (13.3, 13.3, 0.0) mm, has zero area");
  EXPECT_EQ(message({0, 3, 4}), "back_of_head's triangle 1 of 1, at (10.0, 10.0, 0.0) mm, has zero area");  // collinear
  EXPECT_EQ(message({1, 4, 3, 2, 1, 0}),
            "back_of_head's triangle 2 of 2, at (3.3, 3.3, 0.0) mm, repeats a triangle of respirator_inner");
}

// A chin group renamed in the surface, or the chin missing from head_layers_mm, gave a head
// without chin layers and exit 0.
TEST(require_stack_for_every_part, names_a_part_without_a_stack_or_a_stack_without_a_part) {
  const layering::FeModel surface = fixtures::niosh_surface(kNioshMedium, 6.0);
  const auto stacks = layering::read_stacks(kMaterials, "head");
  auto message = [&](const layering::FeModel& s, const std::map<std::string, layering::Stack>& st) {
    return bad_input_message([&] { layering::require_stack_for_every_part(s, st, "s.msh", "m.json"); });
  };
  EXPECT_EQ(message(surface, stacks), "no error");
  auto no_chin_stack = stacks;
  no_chin_stack.erase("chin");
  EXPECT_EQ(message(surface, no_chin_stack), "m.json: no layer stack for part chin of s.msh: it would stay a bare surface");
  layering::FeModel renamed = surface;
  for (auto& b : renamed.blocks)
    if (b.name == "chin") b.name = "jaw";
  EXPECT_EQ(message(renamed, stacks),
            "s.msh: no triangle group chin, which m.json layers (a renamed group, or not surface_mesh's output?)");
  // the other kind's surface (the message gave no hint at --kind)
  layering::FeModel respirator = surface;
  respirator.blocks = {layering::Block{"respirator_inner", 2, 3, surface.find("chin")->conn}};
  EXPECT_EQ(message(respirator, stacks),
            "s.msh: no triangle group chin, which m.json layers (a respirator's surface: give --kind respirator)");
  EXPECT_EQ(message(surface, layering::read_stacks(kMaterials, "respirator")),
            "s.msh: no triangle group respirator_inner, which m.json layers (a head's surface: leave out --kind respirator)");
}

TEST(parse_elements_per_tissue, takes_materials_of_the_stacks_with_counts_1_to_20) {
  const auto stacks = layering::read_stacks(kMaterials, "head");
  EXPECT_EQ(layering::parse_elements_per_tissue("fat=3,skin=20", stacks), (std::map<std::string, int>{{"fat", 3}, {"skin", 20}}));
  EXPECT_TRUE(layering::parse_elements_per_tissue("", stacks).empty());
  auto message = [&](const std::string& text) {
    return error_message(pipeline::ErrorKind::usage, [&] { layering::parse_elements_per_tissue(text, stacks); });
  };
  for (const char* bad : {"fat=2.5", "fat=0", "fat=21", "fat=1e9", "fat=", "=3", "fat", "fat=-1"})
    EXPECT_EQ(message(bad), "--elements-per-tissue: '" + std::string(bad) + "', expected material=N with N an integer 1..20");
  EXPECT_EQ(message("unobtainium=2"), "--elements-per-tissue: 'unobtainium=2': no layer of unobtainium in the stacks");
  EXPECT_EQ(message("seal_layer=2"), "--elements-per-tissue: 'seal_layer=2': no layer of seal_layer in the stacks");
  EXPECT_EQ(message("skin=2,skin=3"), "--elements-per-tissue: skin given twice");
}

// Cheek names swapped by hand in surface.msh were layered and assembled with the left cheek on the
// subject's right (+x is the left), exit 0.
TEST(require_cheeks_on_their_sides, names_a_cheek_on_the_wrong_side) {
  layering::FeModel m;
  m.nodes = {{50, 0, 0}, {60, 0, 0}, {50, 10, 0}, {-50, 0, 0}, {-60, 0, 0}, {-50, 10, 0}};
  m.blocks.push_back(layering::Block{"left_cheek", 2, 3, {0, 1, 2}});
  m.blocks.push_back(layering::Block{"right_cheek", 2, 3, {3, 5, 4}});
  const auto message = [&] {
    return bad_input_message([&] { layering::require_cheeks_on_their_sides(m, "surface.msh"); }, "surface.msh");
  };
  EXPECT_EQ(message(), "no error");
  std::swap(m.blocks[0].name, m.blocks[1].name);
  EXPECT_EQ(message(), "group left_cheek lies at mean x = -53.3333 mm, on the subject's right (+x is the left in align's "
                       "frame): cheek labels swapped?");
}

// An edited surface that is not one oriented sheet (a flipped triangle, a fin, a loose triangle)
// ran 60 thinning passes and ended as "wedges still inverted, distorted or intersecting".
TEST(require_one_oriented_sheet, names_a_flipped_or_fin_edge_and_loose_pieces) {
  layering::FeModel m;
  m.nodes = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {10, 10, 0}, {5, 5, 10}, {50, 50, 0}, {60, 50, 0}, {50, 60, 0}};
  m.blocks.push_back(layering::Block{"respirator_inner", 2, 3, {0, 1, 2, 1, 3, 2}});
  const auto message = [&] {
    return bad_input_message([&] { layering::require_one_oriented_sheet(m, "surface.msh"); }, "surface.msh");
  };
  EXPECT_EQ(message(), "no error");
  m.blocks[0].conn = {0, 1, 2, 1, 2, 3};  // the second triangle flipped
  EXPECT_EQ(message(), "the edge from (10.0, 0.0, 0.0) mm to (0.0, 10.0, 0.0) mm runs the same way in two triangles: a "
                       "triangle flipped, or more than two triangles on an edge");
  m.blocks[0].conn = {0, 1, 2, 1, 3, 2, 2, 1, 4};  // a fin on the shared edge 1-2
  EXPECT_NE(message().find("runs the same way in two triangles"), std::string::npos);
  m.blocks[0].conn = {0, 1, 2, 1, 3, 2};
  m.blocks.push_back(layering::Block{"back_of_head", 2, 3, {5, 6, 7}});  // every triangle group counts
  EXPECT_EQ(message(), "its triangles are in 2 separate pieces, expected one surface");
}

// A sheet folded back on itself (as the real Flex face seal's lip rolls inward, 137-158° between
// neighbouring triangles) leaves no column direction at the fold that gives wedges of either side
// a scaled Jacobian of 0.2; the fix loop's error named only a bad wedge, now also the fold.
TEST(build_layers, a_fold_too_sharp_for_wedges_is_named_in_the_error) {
  layering::FeModel surface;
  layering::Block inner{"respirator_inner", 2, 3, {}};
  const double fold = 165 * M_PI / 180;  // the angle between the two flaps' normals
  for (int j = 0; j <= 4; ++j)
    for (int i = -3; i <= 3; ++i) {
      const double u = 4.0 * i;
      surface.nodes.push_back(i <= 0 ? Eigen::Vector3d(u, 4.0 * j, 0) : Eigen::Vector3d(u * std::cos(fold), 4.0 * j, u * std::sin(fold)));
    }
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 6; ++i) {
      const int a = 7 * j + i, b = a + 1, c = a + 7, d = a + 8;
      inner.conn.insert(inner.conn.end(), {a, b, d, a, d, c});
    }
  surface.blocks = {inner};
  const std::string message = error_message(pipeline::ErrorKind::algorithm, [&] {
    layering::build_layers(surface, layering::read_stacks(kMaterials, "respirator"), {}, nullptr);
  });
  EXPECT_NE(message.find("wedges still inverted, distorted or intersecting after 60 thinning passes"), std::string::npos) << message;
  EXPECT_NE(message.find("; the skin's sharpest fold there is 165 deg at (0.0, "), std::string::npos) << message;
}

// A stack the part's curvature cannot hold is thinned column by column; the stage said nothing
// (a 30 mm cheek fat: the cheek's skin 23 % thinner than asked, exit 0). Groups more than 5 %
// short of their mid-area x thickness now get a warning line each, worst first.
TEST(volume_shortfall_warnings, names_each_group_more_than_5_percent_short) {
  layering::LayerReport rep;
  rep.reduced_columns = 225;
  const auto group = [](const char* name, double volume) {
    layering::LayerVolume v;
    v.group = name, v.volume = volume, v.mid_area_volume = 1000;
    return v;
  };
  rep.volumes = {group("forehead_skin", 961), group("left_cheek_skin", 771), group("left_cheek_fat", 940),
                 group("chin_bone", 1010)};
  EXPECT_EQ(layering::volume_shortfall_warnings(rep),
            (std::vector<std::string>{"left_cheek_skin holds 22.9 % less than its mid-area x thickness (225 columns of the model "
                                      "thinned where the stack does not fit)",
                                      "left_cheek_fat holds 6.0 % less than its mid-area x thickness (225 columns of the model "
                                      "thinned where the stack does not fit)"}));
  rep.volumes.erase(rep.volumes.begin() + 1, rep.volumes.begin() + 3);
  EXPECT_TRUE(layering::volume_shortfall_warnings(rep).empty());  // 3.9 % short: the chain's heads
}
