// Tests of meshing::surface_mesh and the `surface_mesh` command line, on the NIOSH medium
// headform taken through the pipeline's order: repair -> segment (landmarks fixture of
// tests/segment) -> fit (2 mm, the fit default) -> surface_mesh.
#include <gtest/gtest.h>

#include <gmsh.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
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
  // (scanned, reconstructed), 2,979 on the generated medium head (13,484 wedges). The window,
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

TEST(surface_mesh_cli, writes_msh_meshio_reads_and_fails_cleanly) {
  const std::string fitted = (dir / "fitted.ply").string(), out = (dir / "surface.msh").string();
  pipeline::write_surface_mesh(fitted, fitted_medium());
  const std::string bin = std::string(BIN_DIR) + "/surface_mesh --in " + fitted + " --out ";
  ASSERT_EQ(run_command(bin + out + " 2>/dev/null"), 0);
  const std::string check = std::string(SYSTEM_PYTHON) + " -c \"import meshio; m = meshio.read('" + out +
                            "'); assert set(m.cell_sets) >= {'forehead','left_cheek','right_cheek','chin','back_of_head'}\"";
  EXPECT_EQ(std::system(check.c_str()), 0);
  // An unreachable quality threshold is an algorithm failure: exit 3, no file.
  const std::string bad = (dir / "bad.msh").string();
  EXPECT_EQ(run_command(bin + bad + " --min-gamma 0.99 2>/dev/null"), 3);
  EXPECT_FALSE(fs::exists(bad));
}
