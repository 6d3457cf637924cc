// Tests of meshing::surface_mesh and the `surface_mesh` command line, on the NIOSH medium
// headform taken through the pipeline's order: repair -> segment (landmarks fixture of
// tests/segment) -> fit (2 mm, the fit default) -> surface_mesh.
#include <gtest/gtest.h>

#include <gmsh.h>

#include <CGAL/Polygon_mesh_processing/measure.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "layering/internal/segment_landmarks.h"
#include "layering/segment.h"
#include "meshing/surface_mesh.h"
#include "pipeline/error.h"
#include "pipeline/gmsh_session.h"
#include "pipeline/read_scan.h"
#include "pipeline/write_mesh.h"
#include "scan2cad/fit.h"
#include "scan2cad/repair.h"
#include "../file_text.h"
#include "../run_command.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;

namespace {

const fs::path dir = scratch_dir();

// NIOSH medium (already in the head frame, mm) repaired with the repair defaults, segmented and
// fitted as `make case=...` does.
pipeline::SurfaceMesh fitted_medium() {
  fs::create_directories(dir);
  const pipeline::Scan scan = pipeline::read_scan(std::string(SHARED_DATA_DIR) + "/headforms/NIOSH_medium_20k.stl");
  pipeline::SurfaceMesh mesh = scan2cad::repair(scan.soup, scan2cad::ScanKind::head, {});
  layering::segment_head(mesh, layering::internal::read_segment_landmarks(std::string(SOURCE_DIR) +
                                                                          "/tests/segment/niosh_medium_landmarks.json"));
  return scan2cad::remesh_parts(mesh, "head", 2.0);
}

}  // namespace

TEST(surface_mesh, niosh_medium_conforming_good_quality_layering_size) {
  const pipeline::SurfaceMesh fitted = fitted_medium();
  ASSERT_GT(fitted.number_of_faces(), 0u);
  const pipeline::GmshSession gmsh_session;  // the mesh stays in gmsh's model for the checks below
  const auto parts = meshing::surface_mesh(fitted, "head", meshing::default_size_mm, meshing::default_back_size_mm);
  ASSERT_EQ(parts.size(), 5u);
  std::size_t face_triangles = 0;
  for (const auto& p : parts) {
    SCOPED_TRACE(p.name);
    EXPECT_GE(p.min_gamma, 0.3);  // task requirement; measured 0.50-0.69 from the fitted mesh
    if (p.name != "back_of_head") face_triangles += p.triangles;
  }
  // Layering size: layers makes ~4.5 wedges per face triangle with the default stacks, and the
  // paper's medium head has 13,570 wedges, so ~3,000 face triangles; the default 6.4 mm gives
  // 3,174 here (the NIOSH STL repaired, fixture landmarks), 2,770 on the NIOSH medium chain
  // (scanned, reconstructed), 2,879 on the generated medium head (13,049 wedges; on 2026-12-06). The window,
  // ~3,000 +- 17 %, allows for the remeshing's variation with the input.
  std::printf("NIOSH medium at the default size: %zu face-part triangles\n", face_triangles);
  EXPECT_GT(face_triangles, 2500u);
  EXPECT_LT(face_triangles, 3500u);
  // Physical groups named per part.
  std::set<std::string> names;
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, 2);
  for (auto& [dim, tag] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(dim, tag, name);
    names.insert(name);
  }
  EXPECT_EQ(names, (std::set<std::string>{"back_of_head", "forehead", "left_cheek", "right_cheek", "chin"}));
  // Conforming: one node set for the whole closed head, so V - E + F = 2 with E = 3F/2 (every
  // edge shared by exactly two triangles, across part boundaries too).
  std::set<std::size_t> used;
  std::size_t triangles = 0;
  for (auto& [dim, tag] : groups) {
    std::vector<std::size_t> tags, nodes;
    gmsh::model::mesh::getElementsByType(2, tags, nodes, tag);
    used.insert(nodes.begin(), nodes.end());
    triangles += tags.size();
  }
  EXPECT_EQ(long(used.size()) - long(3 * triangles / 2) + long(triangles), 2);
}

// gmsh 4.8's createTopology numbered the points and curves between the parts, directed the curves
// and listed each part's boundary in pointer order: the same fitted head meshed from a relative and
// from an absolute path gave two surface.msh files. build_part_model renumbers them from the node
// tags (internal/number_topology.h); this checks each rule on the model it leaves.
// The retries mesh finer and finer: on a generated head --size 1 with the 7 mm back failed at
// every size and ran past 400 s and 1 GB. A retry past the triangle budget is not tried; the
// error says why. Here a budget just under the first retry's estimate: one attempt, then the error.
TEST(surface_mesh, retries_stop_at_the_triangle_budget) {
  const pipeline::SurfaceMesh fitted = fitted_medium();
  const pipeline::GmshSession gmsh_session;
  const double first_retry_mm = meshing::default_size_mm * meshing::retry_size_factor;
  const double budget = CGAL::Polygon_mesh_processing::area(fitted) / (std::sqrt(3.0) / 4 * first_retry_mm * first_retry_mm) - 1;
  pipeline::Progress progress("surface_mesh_test", 0);
  meshing::SurfaceMeshRetries retries;
  try {
    meshing::surface_mesh(fitted, "head", meshing::default_size_mm, meshing::default_back_size_mm, 0.99,
                          meshing::default_max_retries, &retries, &progress, budget);
    ADD_FAILURE() << "no error";
  } catch (const pipeline::Error& e) {
    EXPECT_EQ(e.kind, pipeline::ErrorKind::algorithm);
    const std::string message = e.what();
    EXPECT_NE(message.find(" < 0.99 at size 6.4 mm, at ("), std::string::npos) << message;
    EXPECT_NE(message.find(": the next size, 5.12 mm, would make ~"), std::string::npos) << message;
    EXPECT_NE(message.find("; try a larger --size, or a lower --min-gamma"), std::string::npos) << message;
  }
}

// What the size options may be: without --back-size the back follows --size (min(7, 2 x size));
// a back more than 2.5 times the size is refused before any work.
TEST(surface_mesh, the_back_size_follows_the_size) {
  EXPECT_EQ(meshing::default_back_size_for(meshing::default_size_mm), meshing::default_back_size_mm);
  EXPECT_EQ(meshing::default_back_size_for(2.0), 4.0);
  EXPECT_EQ(meshing::default_back_size_for(10.0), 10.0);  // never finer than the face parts
}

TEST(surface_mesh, points_and_curves_numbered_and_directed_by_node_tags) {
  const pipeline::SurfaceMesh fitted = fitted_medium();
  const pipeline::GmshSession gmsh_session;
  meshing::surface_mesh(fitted, "head", meshing::default_size_mm, meshing::default_back_size_mm);
  auto nodes_of = [](int dim, int tag) {
    std::vector<std::size_t> nodes;
    std::vector<double> xyz, parametric;
    gmsh::model::mesh::getNodes(nodes, xyz, parametric, dim, tag, false, false);
    return nodes;
  };
  auto lines_of = [](int tag) {
    std::vector<std::size_t> elements, nodes;
    gmsh::model::mesh::getElementsByType(1, elements, nodes, tag);
    return nodes;
  };
  gmsh::vectorpair points, curves, surfaces;
  gmsh::model::getEntities(points, 0);
  gmsh::model::getEntities(curves, 1);
  gmsh::model::getEntities(surfaces, 2);
  ASSERT_GE(points.size(), 2u);  // the five parts meet at corners
  ASSERT_GE(curves.size(), 4u);
  std::map<int, std::size_t> point_node;
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(points[i].second, int(i) + 1);
    const auto nodes = nodes_of(0, points[i].second);
    ASSERT_EQ(nodes.size(), 1u);
    point_node[points[i].second] = nodes[0];
    if (i > 0) {
      EXPECT_LT(point_node[points[i - 1].second], nodes[0]) << "point " << points[i].second;
    }
  }
  std::vector<std::size_t> previous_key;
  std::map<int, std::pair<std::size_t, std::size_t>> first_line;
  for (const auto& [dim, tag] : curves) {
    SCOPED_TRACE("curve " + std::to_string(tag));
    const auto lines = lines_of(tag);
    ASSERT_GE(lines.size(), 2u);
    std::vector<std::size_t> key = lines;  // its node tags in increasing order
    std::sort(key.begin(), key.end());
    key.erase(std::unique(key.begin(), key.end()), key.end());
    EXPECT_GT(key, previous_key) << "curves numbered by their node tags";
    previous_key = key;
    for (std::size_t k = 2; k + 1 < lines.size(); k += 2) EXPECT_EQ(lines[k], lines[k - 1]) << "lines walk the curve";
    std::vector<int> up, ends;
    gmsh::model::getAdjacencies(1, tag, up, ends);
    ASSERT_EQ(ends.size(), 2u);
    if (ends[0] != ends[1]) {
      EXPECT_LT(point_node.at(ends[0]), point_node.at(ends[1]));
      EXPECT_EQ(lines.front(), point_node.at(ends[0]));
      EXPECT_EQ(lines.back(), point_node.at(ends[1]));
    }
    const auto own = nodes_of(1, tag);
    EXPECT_TRUE(std::is_sorted(own.begin(), own.end()));
    first_line[tag] = {lines[0], lines[1]};
  }
  std::map<int, std::vector<int>> signs;  // curve → its sign in each surface that it bounds
  for (const auto& [dim, tag] : surfaces) {
    SCOPED_TRACE("surface " + std::to_string(tag));
    std::vector<std::size_t> elements, triangles;
    gmsh::model::mesh::getElementsByType(2, elements, triangles, tag);
    std::set<std::pair<std::size_t, std::size_t>> half_edges;
    for (std::size_t k = 0; k + 2 < triangles.size(); k += 3)
      for (std::size_t j = 0; j < 3; ++j) half_edges.insert({triangles[k + j], triangles[k + (j + 1) % 3]});
    gmsh::vectorpair boundary;
    gmsh::model::getBoundary({{2, tag}}, boundary, false, true, false);
    int previous = 0;
    for (const auto& [curve_dim, curve] : boundary) {
      EXPECT_GT(std::abs(curve), previous) << "boundary in tag order";
      previous = std::abs(curve);
      EXPECT_EQ(curve > 0, half_edges.count(first_line.at(std::abs(curve))) == 1) << "curve " << curve;
      signs[std::abs(curve)].push_back(curve > 0 ? 1 : -1);
    }
  }
  for (const auto& [curve, s] : signs) {  // a closed head: every curve between two parts, run both ways
    ASSERT_EQ(s.size(), 2u) << "curve " << curve;
    EXPECT_EQ(s[0] + s[1], 0) << "curve " << curve;
  }
}

TEST(surface_mesh_cli, writes_msh_meshio_reads_and_fails_cleanly) {
  const std::string fitted = (dir / "fitted.ply").string(), out = (dir / "surface.msh").string();
  pipeline::write_surface_mesh(fitted, fitted_medium());
  const std::string bin = std::string(BIN_DIR) + "/surface_mesh --in " + fitted + " --out ";
  ASSERT_EQ(run_command(bin + out + " 2>/dev/null"), 0);
  // The same input named by a relative path, from another folder: the same bytes (the two runs
  // gave two surface.msh files with points 4 and 5 swapped before number_topology_by_node_tags).
  const std::string relative = (dir / "relative.msh").string();
  ASSERT_EQ(run_command("cd " + dir.string() + " && " + std::string(BIN_DIR) +
                        "/surface_mesh --in fitted.ply --out relative.msh 2>/dev/null"),
            0);
  EXPECT_EQ(file_text(relative), file_text(out));
  const std::string check = std::string(SYSTEM_PYTHON) + " -c \"import meshio; m = meshio.read('" + out +
                            "'); assert set(m.cell_sets) >= {'forehead','left_cheek','right_cheek','chin','back_of_head'}\"";
  EXPECT_EQ(std::system(check.c_str()), 0);
  // A back of 7 mm beside 2 mm face parts: refused at once (exit 1), not 251 s of failed retries.
  ASSERT_EQ(run_command(bin + out + ".coarse_back.msh --size 2 --back-size 7 2> " + (dir / "err.txt").string()), 1);
  EXPECT_NE(file_text((dir / "err.txt").string())
                .find("surface_mesh: --back-size 7 mm is more than 2.5 times --size 2 mm: the cut between them gets no "
                      "good triangle at any size; give at most 5 mm, or leave --back-size out (4 mm)"),
            std::string::npos);
  // An unreachable quality threshold is an algorithm failure: exit 3, no file.
  const std::string bad = (dir / "bad.msh").string();
  EXPECT_EQ(run_command(bin + bad + " --min-gamma 0.99 2>/dev/null"), 3);
  EXPECT_FALSE(fs::exists(bad));
}
