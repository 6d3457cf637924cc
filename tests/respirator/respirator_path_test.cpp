// The respirator path downstream of repair: align -> segment (inner face) -> fit -> surface_mesh
// -> layers, on the six generated cups (the generator's clean closed shell, wall 1.5 mm, as a
// perfect reconstruction would give it), and align -> segment -> fit on the two real parts in
// ../shared/data/respirator-parts/. Each test prints its figures (RecordProperty and stdout).
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <gmsh.h>

#include <Eigen/Geometry>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "layering/layers.h"
#include "layering/segment.h"
#include "meshing/surface_mesh.h"
#include "pipeline/error.h"
#include "pipeline/gmsh_session.h"
#include "scan2cad/align.h"
#include "scan2cad/fit.h"
#include "../file_text.h"
#include "../generated_cup.h"
#include "../run_command.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;
namespace PMP = CGAL::Polygon_mesh_processing;
using pipeline::SurfaceMesh;

namespace {

const fs::path dir = scratch_dir();

double area(const SurfaceMesh& m) { return PMP::area(m); }

// Rotation angle [deg] between two rotations.
double angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a * b.transpose()).angle() * 180.0 / M_PI;
}

struct Aligned {
  SurfaceMesh mesh;
  scan2cad::AlignResult result;
};

Aligned aligned(SurfaceMesh mesh) {
  scan2cad::AlignOptions opt;
  opt.kind = scan2cad::AlignKind::respirator;
  const auto r = scan2cad::align(mesh, opt);
  scan2cad::apply_transform(mesh, r.transform);
  return {mesh, r};
}

}  // namespace

class GeneratedCup : public ::testing::TestWithParam<const char*> {};

TEST_P(GeneratedCup, align_segment_fit_surface_mesh_layers) {
  const std::string id = GetParam();
  const SurfaceMesh shell = clean_cup(id);
  ASSERT_TRUE(CGAL::is_closed(shell));

  // align: the cup given in a random rigid placement lands in the same frame as the upright one.
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  M.block<3, 3>(0, 0) = (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()) *
                         Eigen::AngleAxisd(-2.1, Eigen::Vector3d(-2, 0.5, 1).normalized())).toRotationMatrix();
  M.block<3, 1>(0, 3) = Eigen::Vector3d(40, -75, 210);
  SurfaceMesh moved = shell;
  scan2cad::apply_transform(moved, M);
  const Aligned upright = aligned(shell), placed = aligned(moved);
  const Eigen::Matrix4d placed_total = placed.result.transform * M;
  const double rot_err_deg = angle_deg(placed_total.block<3, 3>(0, 0), upright.result.transform.block<3, 3>(0, 0));
  double shift_err_mm = 0;
  for (auto v : shell.vertices()) {
    const auto& q = shell.point(v);
    const Eigen::Vector4d x(q.x(), q.y(), q.z(), 1);
    shift_err_mm = std::max(shift_err_mm, (placed_total * x - upright.result.transform * x).head<3>().norm());
  }
  EXPECT_LE(rot_err_deg, 2.0);
  EXPECT_LE(shift_err_mm, 2.0);  // largest displacement of any vertex between the two frames

  // segment: the inner face of the thin shell, an open disk whose rim is the inner sheet's edge.
  SurfaceMesh inner = placed.mesh;
  layering::RespiratorSegmentInfo info;
  const layering::PartStats seg = layering::segment_respirator(inner, &info);
  EXPECT_TRUE(info.thin_shell);
  EXPECT_NEAR(info.wall_mm, 1.5, 0.1);  // the generator's wall
  EXPECT_EQ(info.faces_dropped + seg.faces, placed.mesh.number_of_faces());  // every dropped face counted
  EXPECT_EQ(seg.euler, 1);
  EXPECT_EQ(seg.boundary_loops, 1);
  // The inner sheet is a little smaller than the outer one (offset outward on a dome) and the
  // rim strip (1.5 mm x the rim length) is not part of it: 45-50 % of the shell's area.
  const double share = seg.area_mm2 / area(shell);
  EXPECT_GT(share, 0.45);
  EXPECT_LT(share, 0.50);
  EXPECT_LT(mean_normal_z(inner), -0.3);  // looks toward the face

  // The inner face alone, turned over (a reconstruction that keeps one side of the wall): kept
  // whole as a single open sheet and turned back toward the face.
  SurfaceMesh sheet = inner;
  PMP::reverse_face_orientations(sheet);
  layering::RespiratorSegmentInfo sheet_info;
  const layering::PartStats sheet_seg = layering::segment_respirator(sheet, &sheet_info);
  EXPECT_FALSE(sheet_info.thin_shell);
  EXPECT_EQ(sheet_seg.faces, seg.faces);
  EXPECT_EQ(sheet_info.faces_dropped, 0u);
  EXPECT_EQ(sheet_seg.euler, 1);
  EXPECT_LT(mean_normal_z(sheet), -0.3);

  // fit (the fit CLI's default 2 mm): deviation budget of issue 3.
  const SurfaceMesh fitted = scan2cad::remesh_parts(inner, "respirator", 2.0);
  const auto dev = scan2cad::fit_deviation(inner, fitted, "respirator");
  ASSERT_EQ(dev.size(), 1u);
  EXPECT_LE(dev[0].rms_mm, 0.2);
  EXPECT_LE(dev[0].max_mm, 1.0);
  const auto fitted_stats = layering::part_stats(fitted, layering::respirator_inner);
  EXPECT_EQ(fitted_stats.euler, 1);
  EXPECT_EQ(fitted_stats.boundary_loops, 1);

  // surface_mesh (the CLI's default size), written as msh and read back by meshio.
  fs::create_directories(dir);
  const std::string msh = (dir / (id + "_surface.msh")).string();
  std::vector<meshing::SurfaceMeshPart> parts;
  {
    const pipeline::GmshSession gmsh_session;
    parts = meshing::surface_mesh(fitted, "respirator", meshing::default_size_mm, 0.0);
    gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
    gmsh::write(msh);
  }
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].name, "respirator_inner");
  EXPECT_GE(parts[0].min_gamma, 0.3);
  const std::string check = std::string(SYSTEM_PYTHON) + " -c \"import meshio; m = meshio.read('" + msh +
                            "'); assert 'respirator_inner' in m.cell_sets\"";
  EXPECT_EQ(std::system(check.c_str()), 0) << "meshio cannot read " << msh;

  // layers: 1 mm face-seal + 2 mm outer wedge layers.
  const auto stacks = layering::read_stacks(std::string(SOURCE_DIR) + "/data/materials.json", "respirator");
  layering::LayerOptions opt;
  opt.kind = "respirator";
  layering::LayerReport rep;
  const layering::FeModel model = layering::build_layers(layering::read_fe_model(msh), stacks, opt, &rep);
  EXPECT_EQ(rep.wedges, 2 * parts[0].triangles);
  EXPECT_GT(rep.min_volume, 0.0);
  EXPECT_GE(rep.min_scaled_jacobian, 0.2);
  EXPECT_EQ(rep.intersecting_pairs, 0u);
  ASSERT_EQ(rep.volumes.size(), 2u);
  EXPECT_EQ(rep.volumes[0].group, "respirator_seal");
  EXPECT_EQ(rep.volumes[1].group, "respirator_outer");
  for (const auto& v : rep.volumes) {
    SCOPED_TRACE(v.group);
    EXPECT_NEAR(v.volume / v.mid_area_volume, 1.0, 0.05);  // part x layer volume vs area x thickness
  }
  EXPECT_NE(model.find("respirator_rim"), nullptr);

  // How far the aligned frame is turned from the frame the cup was designed in (on the average
  // face, head frame): printed, not asserted (the rim's nose-chin line is only about vertical).
  const double design_tilt_deg = angle_deg(upright.result.transform.block<3, 3>(0, 0), Eigen::Matrix3d::Identity());
  std::printf("[ figures  ] %-13s align %.2f deg %.2f mm (%.1f deg from the design frame) | inner face %.0f mm2 (%.1f %% of shell) wall %.2f mm | "
              "fit rms %.3f max %.3f mm | %zu triangles gamma min %.3f | %zu wedges SJ min %.3f\n",
              id.c_str(), rot_err_deg, shift_err_mm, design_tilt_deg, seg.area_mm2, 100 * share, info.wall_mm, dev[0].rms_mm,
              dev[0].max_mm, parts[0].triangles, parts[0].min_gamma, rep.wedges, rep.min_scaled_jacobian);
}

INSTANTIATE_TEST_SUITE_P(six_cups, GeneratedCup,
                         ::testing::Values("onesize", "twosize-s", "twosize-m", "threesize-s", "threesize-lm",
                                           "threesize-xl"),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

// The real parts are closed thin shells, but not cups: each is a frame open at both ends (the
// Flex face seal a funnel with an inward-rolled lip at its wide end, the Conforming invert a
// tray with a port hole in its plate and an inward flap at its open end), so their inner face is
// an annulus (Euler 0, two rims), not a disk.
class RealPart : public ::testing::TestWithParam<const char*> {};

TEST_P(RealPart, align_segment_and_fit_inner_face) {
  const std::string name = GetParam();
  const std::string path = std::string(SHARED_DATA_DIR) + "/respirator-parts/" + name + ".stl";
  pipeline::Unit unit = pipeline::Unit::automatic;
  const Aligned a = aligned(scan2cad::load_surface_any_unit(path, 130.0, &unit));
  EXPECT_EQ(unit, pipeline::Unit::mm);
  EXPECT_GT(a.result.symmetry_inliers, 0.8);
  SurfaceMesh inner = a.mesh;
  layering::RespiratorSegmentInfo info;
  const layering::PartStats seg = layering::segment_respirator(inner, &info);
  EXPECT_TRUE(info.thin_shell);
  EXPECT_EQ(seg.euler, 0);
  EXPECT_EQ(seg.boundary_loops, 2);
  const SurfaceMesh fitted = scan2cad::remesh_parts(inner, "respirator", 2.0);
  const auto dev = scan2cad::fit_deviation(inner, fitted, "respirator");
  ASSERT_EQ(dev.size(), 1u);
  EXPECT_LE(dev[0].rms_mm, 0.2);
  EXPECT_LE(dev[0].max_mm, 1.0);
  std::printf("[ figures  ] %-20s symmetry rms %.3f mm inliers %.0f %% | wall %.2f mm, %.0f %% paired | inner face "
              "%.0f mm2 euler %d loops %d | fit rms %.3f max %.3f mm\n",
              name.c_str(), a.result.symmetry_rms_mm, 100 * a.result.symmetry_inliers, info.wall_mm,
              100 * info.paired_fraction, seg.area_mm2, seg.euler, seg.boundary_loops, dev[0].rms_mm, dev[0].max_mm);
}

INSTANTIATE_TEST_SUITE_P(shared_parts, RealPart, ::testing::Values("Flex_Face_Seal_v9-M", "Conforming_Invert_M"),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

namespace {

// Runs one stage program of BIN_DIR; returns its exit code, stderr in *err.
int run_stage(const std::string& args, std::string* err) {
  const std::string log = (dir / "stage_stderr.txt").string();
  const int code = run_command(std::string(BIN_DIR) + "/" + args + " >/dev/null 2>" + log);
  *err = file_text(log);
  return code;
}

}  // namespace

// The stage programs in Makefile.cases' order on the generator's clean onesize cup; bad input to
// segment and fit gives one error line naming the file, exit 2, and no output.
// The real Conforming cup through the stage programs as a case runs them. It failed twice: repair
// kept the STL's 4 mm gap open as the cup's "rim" (a closed shell has none), and surface_mesh
// found gamma 0.16 at 6.4 mm between two creases 1 mm apart (a rib). Now the gap is filled and
// surface_mesh meshes again finer until every triangle is good.
TEST(respirator_cli, the_real_conforming_cup_through_repair_to_layers) {
  fs::create_directories(dir);
  const std::string d = dir.string() + "/conforming_";
  const std::string stl = std::string(SHARED_DATA_DIR) + "/respirator-parts/Conforming_Invert_M.stl";
  std::string err;
  ASSERT_EQ(run_stage("repair --kind respirator --in " + stl + " --out " + d + "repaired.ply", &err), 0) << err;
  EXPECT_NE(err.find(", closed, manifold, no self-intersections"), std::string::npos) << err;
  ASSERT_EQ(run_stage("align --kind respirator --in " + d + "repaired.ply --out " + d + "aligned.ply --transform " + d +
                          "align.json", &err), 0) << err;
  ASSERT_EQ(run_stage("segment --kind respirator --in " + d + "aligned.ply --out " + d + "segmented.ply", &err), 0) << err;
  EXPECT_NE(err.find("boundary loops 2"), std::string::npos) << err;  // its open end and its port hole
  ASSERT_EQ(run_stage("fit --kind respirator --in " + d + "segmented.ply --out " + d + "fitted.ply", &err), 0) << err;
  ASSERT_EQ(run_stage("surface_mesh --kind respirator --in " + d + "fitted.ply --out " + d + "surface.msh", &err), 0) << err;
  EXPECT_NE(err.find("instead of 6.4 mm"), std::string::npos) << err;
  ASSERT_EQ(run_stage("layers --kind respirator --materials " + std::string(SOURCE_DIR) + "/data/materials.json --in " +
                          d + "surface.msh --out " + d + "layers.msh", &err), 0) << err;
  // and at its own limit: one line naming the part, the place and what to change
  EXPECT_EQ(run_stage("surface_mesh --kind respirator --min-gamma 0.95 --in " + d + "fitted.ply --out " + d + "bad.msh", &err), 3);
  EXPECT_NE(err.find("fitted.ply: part respirator_inner: a triangle of quality gamma "), std::string::npos) << err;
  EXPECT_NE(err.find("(and at 6 larger sizes): try a smaller --size, or a lower --min-gamma"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(d + "bad.msh"));
}

TEST(respirator_cli, clean_cup_through_the_stage_programs_and_bad_input) {
  fs::create_directories(dir);
  const std::string d = dir.string() + "/cli_";
  std::string err;
  ASSERT_EQ(run_stage("generate_scan --kind respirator --id onesize --params " + std::string(SOURCE_DIR) +
                          "/data/generator/respirators.json --points 2000 --out " + d + "scan.ply --clean-mesh " + d +
                          "clean.ply",
                      &err), 0) << err;
  ASSERT_EQ(run_stage("align --kind respirator --in " + d + "clean.ply --out " + d + "aligned.ply --transform " + d +
                          "align.json", &err), 0) << err;
  ASSERT_EQ(run_stage("segment --kind respirator --in " + d + "aligned.ply --out " + d + "segmented.ply", &err), 0) << err;
  EXPECT_NE(err.find("thin shell, wall 1.50 mm"), std::string::npos) << err;
  EXPECT_NE(err.find("euler 1  boundary loops 1"), std::string::npos) << err;
  ASSERT_EQ(run_stage("fit --kind respirator --in " + d + "segmented.ply --out " + d + "fitted.ply", &err), 0) << err;
  ASSERT_EQ(run_stage("surface_mesh --kind respirator --in " + d + "fitted.ply --out " + d + "surface.msh", &err), 0) << err;
  ASSERT_EQ(run_stage("layers --kind respirator --materials " + std::string(SOURCE_DIR) + "/data/materials.json --in " +
                          d + "surface.msh --out " + d + "layers.msh", &err), 0) << err;
  const std::string check = std::string(SYSTEM_PYTHON) + " -c \"import meshio; m = meshio.read('" + d +
                            "layers.msh'); assert {'respirator_seal', 'respirator_outer', 'respirator_inner'} <= set(m.cell_sets)\"";
  EXPECT_EQ(std::system(check.c_str()), 0);

  // Bad input: a missing file, and a head-kind label file given to fit as a respirator.
  EXPECT_EQ(run_stage("segment --kind respirator --in " + d + "missing.ply --out " + d + "bad.ply", &err), 2);
  EXPECT_NE(err.find("missing.ply"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(d + "bad.ply"));
  EXPECT_EQ(run_stage("fit --kind respirator --in " + d + "aligned.ply --out " + d + "bad.ply", &err), 2);
  EXPECT_NE(err.find("aligned.ply: parts: no face property \"part\" (run segment first)"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(d + "bad.ply"));
}

// The clean onesize cup's vertices as a scan (both sides of its 1.5 mm wall, no noise), once with
// outward normals and once without (sweep K). With its normals, reconstruct had meshed both sides
// into one surface: repair left 57 handles, segment passed it and fit crashed (SIGSEGV). Without,
// align had turned the cup inside out (its rim band came out sparse, and the wider-end guess took
// the dome's end). Both now go through: normals not used for a respirator, the open side found
// from the rim, an inner face that is a disc.
TEST(respirator_cli, a_clean_cups_points_with_or_without_normals_go_through_right_side_out) {
  fs::create_directories(dir);
  SurfaceMesh cup = clean_cup("onesize");
  PMP::orient_to_bound_a_volume(cup);
  auto normal = cup.add_property_map<SurfaceMesh::Vertex_index, pipeline::Vector>("v:n").first;
  PMP::compute_vertex_normals(cup, normal);
  for (bool with_normals : {true, false}) {
    const std::string d = dir.string() + (with_normals ? "/pn_" : "/p_");
    {
      std::ofstream out(d + "scan.xyz");
      out.precision(9);
      for (auto v : cup.vertices()) {
        const auto& p = cup.point(v);
        out << p.x() << ' ' << p.y() << ' ' << p.z();
        if (with_normals) out << ' ' << normal[v].x() << ' ' << normal[v].y() << ' ' << normal[v].z();
        out << '\n';
      }
    }
    std::string err;
    ASSERT_EQ(run_stage("reconstruct --kind respirator --in " + d + "scan.xyz --out " + d + "reconstructed.ply", &err), 0) << err;
    EXPECT_EQ(err.find("normals are not used for a respirator") != std::string::npos, with_normals) << err;
    EXPECT_NE(err.find("(thin shell, wall 1."), std::string::npos) << err;
    ASSERT_EQ(run_stage("repair --kind respirator --in " + d + "reconstructed.ply --out " + d + "repaired.ply", &err), 0) << err;
    ASSERT_EQ(run_stage("align --kind respirator --in " + d + "repaired.ply --out " + d + "aligned.ply --transform " + d +
                            "align.json", &err), 0) << err;
    // The generator builds the cup in the head frame: its z axis stays +z (the baseline turns it
    // by ~12 deg; inside out, the matrix's (z, z) entry was -0.98).
    const auto frame = nlohmann::json::parse(file_text(d + "align.json"))["matrix"];
    EXPECT_GT(frame[2][2].get<double>(), 0.9) << with_normals;
    ASSERT_EQ(run_stage("segment --kind respirator --in " + d + "aligned.ply --out " + d + "segmented.ply", &err), 0) << err;
    EXPECT_NE(err.find("euler 1  boundary loops 1"), std::string::npos) << err;
    EXPECT_EQ(run_stage("fit --kind respirator --in " + d + "segmented.ply --out " + d + "fitted.ply", &err), 0) << err;
  }
}

// The inner face of a respirator is a disc (a cup) or a ring (the real parts, with a port hole);
// one with no rim (a capped cup) or with handles (both walls merged) is refused by segment.
TEST(segment_respirator, an_inner_face_that_is_not_a_sheet_is_refused) {
  auto stats = [](int euler, int loops) {
    layering::PartStats s;
    s.euler = euler, s.boundary_loops = loops;
    return s;
  };
  EXPECT_NO_THROW(layering::require_respirator_sheet(stats(1, 1)));
  EXPECT_NO_THROW(layering::require_respirator_sheet(stats(0, 2)));
  auto message = [&](int euler, int loops) {
    try {
      layering::require_respirator_sheet(stats(euler, loops));
    } catch (const pipeline::Error& e) {
      EXPECT_EQ(e.kind, pipeline::ErrorKind::bad_input);
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(2, 0), "respirator: its inner face is closed (no rim): a respirator is open toward the face; is its "
                           "rim capped, or is it not a respirator?");
  EXPECT_EQ(message(-113, 1).rfind("respirator: its inner face has 57 handles (Euler characteristic -113, 1 rim(s)), not a "
                                   "sheet", 0), 0u) << message(-113, 1);
  EXPECT_NE(message(-1, 1).find("has 1 handle (Euler"), std::string::npos) << message(-1, 1);
}

// A cup with three 30-40 mm scan holes: repair took a 58 mm patch of its side, past a hole, for
// a table (27 % of it beyond the cup's outline) and cut away a quarter of the cup; the chain then
// failed in layers with a distorted triangle (sweep K). A table is as wide as what stands on it.
TEST(respirator_cli, a_cup_with_large_scan_holes_keeps_its_side) {
  fs::create_directories(dir);
  const std::string d = dir.string() + "/holes_";
  std::string err;
  ASSERT_EQ(run_stage("generate_scan --kind respirator --id onesize --params " + std::string(SOURCE_DIR) +
                          "/data/generator/respirators.json --holes 3 --hole-diameter-mm 30:40 --out " + d + "scan.ply",
                      &err), 0) << err;
  ASSERT_EQ(run_stage("reconstruct --kind respirator --in " + d + "scan.ply --out " + d + "reconstructed.ply", &err), 0) << err;
  EXPECT_EQ(err.find("of a plane the object stood on"), std::string::npos) << err;
  ASSERT_EQ(run_stage("repair --kind respirator --in " + d + "reconstructed.ply --out " + d + "repaired.ply --report " + d +
                          "report.json", &err), 0) << err;
  EXPECT_EQ(err.find("of a plane the object stood on"), std::string::npos) << err;
  EXPECT_EQ(nlohmann::json::parse(file_text(d + "report.json"))["support_faces_removed"].get<int>(), 0);
}
