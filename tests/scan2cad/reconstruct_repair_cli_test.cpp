// CLI tests of the reconstruct and repair programs: bad inputs (one clear line, non-zero exit,
// no output), units, and the real NIOSH medium STL through repair.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "data/generator/scanner_artifacts.h"
#include "pipeline/read_scan.h"
#include "pipeline/write_mesh.h"
#include "scan2cad/reconstruct.h"
#include "../file_text.h"
#include "../last_line.h"
#include "../run_command.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;

namespace {

// One folder per process: ctest runs this binary's tests as parallel processes, and a shared
// folder let one test read the other's stderr (repair_cli failed on reconstruct_cli's message).
const fs::path dir = scratch_dir();
const std::string niosh_medium = std::string(SHARED_DATA_DIR) + "/headforms/NIOSH_medium_20k.stl";

struct CliRun {
  int code;
  std::string err;
};

// `env`: put before the command: variable assignments (e.g. "GLIBC_TUNABLES=...") or a wrapper
// ("timeout 60")
CliRun run(const std::string& args, const std::string& env = "") {
  fs::create_directories(dir);
  const std::string err_path = (dir / "stderr.txt").string();
  const int code = run_command(env + " " + std::string(BIN_DIR) + "/" + args + " 2> " + err_path + " > /dev/null");
  return {code, file_text(err_path)};
}

// A bad input: exit code 2 (bad input), the last stderr line is one "program: file: problem"
// line naming the file, and no output file.
void expect_rejected(const std::string& program, const std::string& in, const std::string& must_say) {
  const std::string out = (dir / (program + "_out.ply")).string();
  fs::remove(out);
  const CliRun r = run(program + " --in " + in + " --kind head --out " + out);
  EXPECT_EQ(r.code, 2) << r.err;
  const std::string last = last_line(r.err);
  EXPECT_EQ(last.rfind(program + ": ", 0), 0u) << last;
  EXPECT_NE(last.find(in), std::string::npos) << "names the file: " << last;
  EXPECT_NE(last.find(must_say), std::string::npos) << last;
  EXPECT_FALSE(fs::exists(out));
}

// `points` sampled on the NIOSH medium surface (40,000: 1.8 mm apart; reconstruct refuses a head
// cloud sparser than 2 mm), scaled by `scale` (1e-3: metres).
pipeline::PointCloud niosh_cloud(double scale, std::size_t points = 40000, bool normals = false) {
  generator::Rng rng{3};
  auto c = generator::sample_surface(generator::triangles_of(pipeline::read_scan(niosh_medium).soup), points, rng);
  if (!normals) c.normals.clear();
  for (auto& p : c.points) p = pipeline::Point(p.x() * scale, p.y() * scale, p.z() * scale);
  return c;
}

}  // namespace

// --out equal to --in replaced the scan with the result, exit 0; now refused before any work.
TEST(repair_cli, an_output_over_its_input_is_refused_and_the_input_kept) {
  fs::create_directories(dir);
  const std::string in = (dir / "same.stl").string();
  fs::copy_file(niosh_medium, in, fs::copy_options::overwrite_existing);
  const CliRun r = run("repair --in " + in + " --out " + in);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(last_line(r.err), "repair: --out '" + in + "' is the same file as --in: each file option needs a file of its " +
                                  "own (an output must not replace an input) (see 'repair --help')");
  EXPECT_EQ(file_text(in), file_text(niosh_medium));
}

// An output that cannot be written is found before the work: repair of the NIOSH STL took ~5 s,
// and reconstruct of a scan minutes, before the write failed. Exit 4, one line naming the output
// and why, and the report of the same run not written either.
TEST(repair_cli, an_output_it_cannot_write_is_refused_before_the_work) {
  fs::create_directories(dir);
  const std::string report = (dir / "unwritten_report.json").string();
  fs::remove(report);
  const CliRun r = run("repair --in " + niosh_medium + " --out /proc/repaired.ply --report " + report);
  EXPECT_EQ(r.code, 4) << r.err;
  EXPECT_EQ(last_line(r.err).rfind("repair: /proc/repaired.ply: cannot write in /proc: ", 0), 0u) << r.err;
  EXPECT_EQ(r.err.find("repair: spikes"), std::string::npos) << r.err;  // no work began
  EXPECT_FALSE(fs::exists(report));
}

TEST(reconstruct_cli, missing_file_is_rejected) { expect_rejected("reconstruct", (dir / "nope.ply").string(), "no such file"); }

TEST(reconstruct_cli, empty_file_is_rejected) { expect_rejected("reconstruct", scratch_file("empty.ply", ""), "empty"); }

TEST(reconstruct_cli, text_file_that_is_not_a_mesh_is_rejected) {
  expect_rejected("reconstruct", scratch_file("letter.stl", "Dear colleague,\nplease find the scan attached.\n"), "not an STL file: text");
}

TEST(reconstruct_cli, nan_coordinates_are_rejected) {
  expect_rejected("reconstruct", scratch_file("nan.xyz", "0 0 0\n100 0 0\nnan 1 2\n0 200 0\n"), "non-finite");
}

TEST(reconstruct_cli, three_points_are_rejected) {
  expect_rejected("reconstruct", scratch_file("three.xyz", "0 0 0\n200 0 0\n0 200 0\n"), "too few");
}

// CGAL's Poisson crashed (SIGSEGV) on points on a plane or a line, and did not finish contouring
// a plane with 0.001 mm of noise; outliers must not hide the plane.
TEST(reconstruct_cli, points_on_a_plane_or_a_line_are_rejected) {
  std::string plane, noisy_plane, line;
  generator::Rng rng{5};
  for (int i = 0; i < 2000; ++i) {
    const double x = rng.uniform() * 200, y = rng.uniform() * 200;
    plane += std::to_string(x) + " " + std::to_string(y) + " 0\n";
    noisy_plane += std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(0.3 * rng.normal()) + "\n";
    line += std::to_string(x) + " 0 0\n";
  }
  std::string with_outliers = noisy_plane;  // 1 %, in the plane's 200 mm box
  for (int i = 0; i < 20; ++i)
    with_outliers += std::to_string(rng.uniform() * 200) + " " + std::to_string(rng.uniform() * 200) + " " +
                     std::to_string(rng.uniform() * 200 - 100) + "\n";
  expect_rejected("reconstruct", scratch_file("plane.xyz", plane), "on a plane or a line");
  expect_rejected("reconstruct", scratch_file("noisy_plane.xyz", noisy_plane), "on a plane or a line");
  expect_rejected("reconstruct", scratch_file("line.xyz", line), "on a plane or a line");
  expect_rejected("reconstruct", scratch_file("plane_with_outliers.xyz", with_outliers), "on a plane or a line");
}

// Uniform noise in a head-sized box went through reconstruct, repair and align (exit 0) and was
// refused only by landmarks, 75 s in; now reconstruct refuses it after its outlier removal.
TEST(reconstruct_cli, points_filling_a_volume_are_rejected) {
  std::string box;
  generator::Rng rng{6};
  for (int i = 0; i < 5000; ++i)
    box += std::to_string(150 * rng.uniform()) + " " + std::to_string(200 * rng.uniform()) + " " +
           std::to_string(250 * rng.uniform()) + "\n";
  expect_rejected("reconstruct", scratch_file("noise.xyz", box), "the points fill a volume instead of lying on a surface");
}

TEST(reconstruct_cli, truncated_binary_ply_is_rejected) {
  const std::string full = (dir / "full.ply").string();
  fs::create_directories(dir);
  pipeline::write_point_cloud(full, niosh_cloud(1.0));
  const std::string b = file_text(full);
  expect_rejected("reconstruct", scratch_file("cut.ply", b.substr(0, b.size() / 2)), "truncated");
}

TEST(reconstruct_cli, truncated_binary_stl_is_rejected) {
  const std::string b = file_text(niosh_medium);
  expect_rejected("reconstruct", scratch_file("cut.stl", b.substr(0, b.size() / 2)), "truncated binary STL: its header declares");
}

TEST(repair_cli, truncated_binary_stl_is_rejected) {
  const std::string b = file_text(niosh_medium);
  expect_rejected("repair", scratch_file("cut_r.stl", b.substr(0, b.size() / 3)), "truncated binary STL: its header declares");
  // two files joined, or bytes appended: assimp's words were those for a file that is no STL
  expect_rejected("repair", scratch_file("joined.stl", b + b),
                  "binary STL: its header declares 20146 triangles (1007384 bytes), the file has 2014768 bytes: a count "
                  "too small, or data appended (two files joined?)");
}

// A flat patch given as a head was closed into two coincident sheets, and CGAL's remeshing then
// crashed (exit 139, no message).
TEST(repair_cli, a_single_triangle_as_a_head_is_rejected) {
  expect_rejected("repair", scratch_file("triangle.off", "OFF\n3 1 0\n0 0 0\n200 0 0\n0 200 0\n3 0 1 2\n"), "flat patch");
}

TEST(repair_cli, a_flat_square_as_a_head_is_rejected) {
  expect_rejected("repair", scratch_file("square.off", "OFF\n4 2 0\n0 0 0\n200 0 0\n200 200 0\n0 200 0\n3 0 1 2\n3 0 2 3\n"),
                  "flat patch");
}

// A respirator given as a head (the default kind) went through reconstruct and repair with exit 0
// and failed only in align ("cannot tell up from down", exit 3): its 107-133 mm are under any
// adult head's 150 mm, and are refused when the unit is guessed. The generated cup's few spikes
// and strays make its box 159 mm across; the guess leaves them out (units.h). Strays too many to
// be left out there (2 % of the points, up to 200 mm across) are outliers to reconstruct, which
// checks the size again without them.
TEST(reconstruct_cli, a_respirator_given_as_a_head_is_rejected) {
  const std::string cup = (dir / "cup_as_head.ply").string();
  ASSERT_EQ(run("generate_scan --kind respirator --id onesize --params " + std::string(SOURCE_DIR) +
                "/data/generator/respirators.json --points 5000 --out " + cup).code, 0);
  expect_rejected("reconstruct", cup, " mm, under 0.6 of an object of about 250 mm: an object of another kind");
  pipeline::PointCloud strays = pipeline::read_scan(cup, {pipeline::Unit::mm}).cloud;
  generator::Rng rng{8};
  for (std::size_t i = 0, n = strays.points.size() / 50; i < n; ++i)
    strays.points.emplace_back(200 * rng.uniform() - 100, 200 * rng.uniform() - 100, 200 * rng.uniform() - 100);
  strays.normals.clear();
  const std::string cup_with_strays = (dir / "cup_with_strays_as_head.ply").string();
  pipeline::write_point_cloud(cup_with_strays, strays);
  expect_rejected("reconstruct", cup_with_strays, "mm, under the 150 mm of the smallest head: an object of another kind");
  expect_rejected("repair", std::string(SHARED_DATA_DIR) + "/respirator-parts/Conforming_Invert_M.stl",
                  "largest extent 132.9 mm, under 0.6 of an object of about 250 mm");
}

// The other way round: a head given as a respirator went through reconstruct, repair and align,
// and segment refused it ("its two sheets are 152 mm apart"). Over 1.6 of a respirator's 130 mm,
// checked without the outliers (reconstruct) and the small pieces (repair): a stray point far off
// is a scanner's. The whole head with its neck is at most 302 mm (NIOSH large), under 400.
TEST(reconstruct_cli, a_head_given_as_a_respirator_is_rejected) {
  const auto with_kind = [&](const std::string& program, const std::string& in, const std::string& must_say) {
    const std::string out = (dir / (program + "_head_as_respirator.ply")).string();
    const CliRun r = run(program + " --in " + in + " --kind respirator --out " + out);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(last_line(r.err).find(in + ": " + must_say), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  };
  const std::string cloud = (dir / "head_as_respirator.ply").string();
  pipeline::write_point_cloud(cloud, niosh_cloud(1.0));
  with_kind("reconstruct", cloud, "point cloud: without its outliers it spans 2");
  with_kind("repair", niosh_medium, "mesh: it spans 285.658 mm, over the 208 mm of the largest respirator: an object of "
                                    "another kind (see --kind), more than the object (shoulders, a stand: crop the scan to the head or "
                                    "the respirator), or in another unit (see --unit)?");
  // a stray point does not make the head too large: the same cloud with one point 0.5 m off (the
  // file's box, 586 mm, is over 400 mm; a metre off, the unit could no longer be told)
  pipeline::PointCloud with_stray = niosh_cloud(1.0);
  with_stray.points.emplace_back(500, 0, 0);
  const std::string stray = (dir / "head_with_a_stray_point.ply").string();
  pipeline::write_point_cloud(stray, with_stray);
  const CliRun r = run("reconstruct --in " + stray + " --kind head --out " + (dir / "stray_out.ply").string());
  EXPECT_EQ(r.code, 0) << r.err;
}

// A head cloud of 20,000 points (2.5 mm apart) lost its ears in the reconstruction, and landmarks
// then put the tragia 40 mm off, on the temple, with exit 0 and no warning; a model was built on
// them (sweep O). Refused here, naming the spacing; --max-spacing-mm moves the limit.
TEST(reconstruct_cli, a_head_cloud_too_sparse_for_its_ears_is_refused) {
  const std::string in = (dir / "sparse_head.xyz").string();
  pipeline::write_point_cloud(in, niosh_cloud(1.0, 20000));
  expect_rejected("reconstruct", in, "point cloud: its points are 2.");
  EXPECT_NE(last_line(run("reconstruct --in " + in + " --kind head --out " + (dir / "x.ply").string()).err)
                .find(" mm apart (mean spacing to 6 neighbours), too sparse for a head: the ears, folds about 1 mm "
                      "thick, are lost between them"),
            std::string::npos);
  const std::string out = (dir / "sparse_head_rec.ply").string();
  const CliRun r = run("reconstruct --in " + in + " --kind head --max-spacing-mm 3 --out " + out);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out));
}

// A scan's own normals are used when they are oriented, and said to be; normals oriented each on
// its own (as often in as out, as some scanners export them) are oriented afresh: taken as they
// were, Poisson ran 9.5 minutes and made 2,134 triangles 435 mm across, which repair then refused
// as too large (sweep O's 300,000-point scan, half its normals flipped).
TEST(reconstruct_cli, a_scans_normals_are_used_when_oriented_and_oriented_afresh_when_not) {
  pipeline::PointCloud cloud = niosh_cloud(1.0, 40000, true);
  ASSERT_EQ(cloud.normals.size(), cloud.points.size());
  const std::string oriented = (dir / "oriented_normals.ply").string();
  pipeline::write_point_cloud(oriented, cloud);
  for (std::size_t i = 0; i < cloud.normals.size(); i += 2) cloud.normals[i] = -cloud.normals[i];
  const std::string unoriented = (dir / "unoriented_normals.ply").string();
  pipeline::write_point_cloud(unoriented, cloud);
  for (const auto& [in, must_say] : {std::pair<std::string, std::string>{oriented, "the scan's own normals are used ("},
                                     {unoriented, "the scan's normals are not oriented (5"}}) {
    const std::string out = in + ".rec.ply";
    const CliRun r = run("reconstruct --in " + in + " --kind head --out " + out);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find(must_say), std::string::npos) << r.err;
    EXPECT_NEAR(pipeline::largest_extent(pipeline::read_scan(out, {pipeline::Unit::mm}).soup.points), 285.7, 2.0) << in;
  }
}

TEST(repair_cli, point_cloud_is_rejected) {
  expect_rejected("repair", scratch_file("cloud.xyz", "0 0 0\n200 0 0\n0 200 0\n0 0 200\n"), "point cloud");
}

TEST(reconstruct_cli, a_scan_in_metres_comes_out_in_mm) {
  const std::string in = (dir / "head_m.xyz").string();
  pipeline::write_point_cloud(in, niosh_cloud(1e-3));
  const std::string out = (dir / "head_m_rec.ply").string();
  fs::remove(out);
  const CliRun r = run("reconstruct --in " + in + " --kind head --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto mesh = pipeline::read_scan(out, {pipeline::Unit::mm});
  // the NIOSH medium headform is 285.7 mm at its largest; the reconstruction of its samples
  // is within 2 mm of that (Poisson smooths the neck corners by about the point spacing)
  EXPECT_NEAR(pipeline::largest_extent(mesh.soup.points), 285.7, 2.0);
  EXPECT_NE(r.err.find(in + ": unit m (detected, --unit forces one): largest extent 285."), std::string::npos) << r.err;
}

// NIOSH medium 20 mm above a table (a 280 mm disc of 8,000 points): Poisson asserted on head and
// table together; now the table is removed first (less the table points the outlier removal took
// at its rim), and the head comes out alone, down to its cap.
TEST(reconstruct_cli, the_table_a_head_was_scanned_on_is_removed) {
  pipeline::PointCloud cloud = niosh_cloud(1.0);
  generator::Rng rng{4};
  const double cap_y_mm = -162.3, table_y_mm = cap_y_mm - 20;
  for (int i = 0; i < 8000; ++i) {
    const double r = 140 * std::sqrt(rng.uniform()), a = 2 * M_PI * rng.uniform();
    cloud.points.push_back(pipeline::Point(r * std::cos(a), table_y_mm + 0.3 * rng.normal(), -50 + r * std::sin(a)));
  }
  const std::string in = (dir / "head_on_table.xyz").string(), out = (dir / "head_on_table_rec.ply").string();
  pipeline::write_point_cloud(in, cloud);
  fs::remove(out);
  const CliRun r = run("reconstruct --in " + in + " --kind head --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find(" points of a plane the object stood on (a table or turntable, 27"), std::string::npos)
      << r.err;
  double lowest_y_mm = 0;
  for (const auto& p : pipeline::read_scan(out, {pipeline::Unit::mm}).soup.points) lowest_y_mm = std::min(lowest_y_mm, p.y());
  EXPECT_NEAR(lowest_y_mm, cap_y_mm, 2.0);
}

// A head in inches was read as cm, 2.54 times too small: both sizes lie in the detection window.
// Now it is refused, naming both readings; --unit in reads it right, and the log line says which
// unit was taken and the size it gives.
TEST(repair_cli, the_unit_taken_and_the_size_it_gives_are_logged) {
  const std::string in = (dir / "niosh_in.ply").string();
  {
    auto soup = pipeline::read_scan(niosh_medium).soup;
    for (auto& p : soup.points) p = pipeline::Point(p.x() / 25.4, p.y() / 25.4, p.z() / 25.4);
    pipeline::write_polygon_soup(in, soup);
  }
  const std::string out = (dir / "niosh_in_rep.ply").string();
  const CliRun guessed = run("repair --in " + in + " --kind head --edge 4 --out " + out);
  EXPECT_EQ(guessed.code, 2) << guessed.err;
  EXPECT_NE(guessed.err.find(in + ": cannot tell the length unit: largest extent 11.24"), std::string::npos) << guessed.err;
  EXPECT_NE(guessed.err.find("force one with --unit cm or --unit in"), std::string::npos) << guessed.err;
  EXPECT_FALSE(fs::exists(out));
  const CliRun forced = run("repair --in " + in + " --kind head --unit in --edge 4 --out " + out);
  ASSERT_EQ(forced.code, 0) << forced.err;
  EXPECT_NE(forced.err.find(in + ": unit in (forced): largest extent 285.7 mm"), std::string::npos) << forced.err;
  // a forced unit that makes no head (inches read as m: 11 m across) is refused, no output
  fs::remove(out);
  const CliRun wrong = run("repair --in " + in + " --kind head --unit m --edge 4 --out " + out);
  EXPECT_EQ(wrong.code, 2) << wrong.err;
  EXPECT_NE(wrong.err.find(in + ": read in m (--unit), its largest extent is 11246.4 mm"), std::string::npos) << wrong.err;
  EXPECT_FALSE(fs::exists(out));
}

// An edge far below the head's scale: the remeshing ran until killed (--edge 0.001 on NIOSH
// medium asks for ~4e11 triangles). Now a usage error before any work, naming the file and the
// count; 0.05 mm (~1.6e8) is refused too, the default 1.5 mm (~1.7e5) passes. Run under
// `timeout 60`, so a regression fails here instead of at ctest's timeout.
TEST(repair_cli, an_edge_too_short_for_the_surface_is_a_usage_error) {
  const std::string out = (dir / "tiny_edge.ply").string();
  for (const char* edge : {"0.001", "0.05"}) {
    SCOPED_TRACE(edge);
    const CliRun r = run("repair --in " + niosh_medium + " --kind head --edge " + edge + " --out " + out, "timeout 60");
    EXPECT_EQ(r.code, 1) << r.err;
    // the last line (after the options, unit and progress lines) is the error, ending in the
    // pointer to --help every usage error ends with
    const std::string line = last_line(r.err);
    EXPECT_EQ(line.rfind("repair: " + niosh_medium + ": --edge " + edge + " mm would make ~", 0), 0u) << line;
    EXPECT_NE(line.find("more than 10 million: choose a longer edge (see 'repair --help')"), std::string::npos) << line;
    EXPECT_EQ(r.err.find("--help"), r.err.rfind("--help")) << r.err;  // no separate hint line
    EXPECT_FALSE(fs::exists(out));
  }
}

// A report that cannot be written (its path is a folder) fails the stage with exit 4 and no
// repaired mesh, so Make does not see a new mesh from a failed run. It is found before the work
// now; until then the mesh was written and removed again when the report failed
// (write_all_or_none, whose own test covers a write failing after another).
TEST(repair_cli, an_unwritable_report_leaves_no_mesh) {
  const std::string out = (dir / "no_report.ply").string(), report = (dir / "report_is_a_folder.json").string();
  std::filesystem::create_directories(report);
  const CliRun r = run("repair --in " + niosh_medium + " --kind head --edge 4 --out " + out + " --report " + report);
  EXPECT_EQ(r.code, 4) << r.err;
  EXPECT_EQ(last_line(r.err), "repair: " + report + ": is a folder, not a file") << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(reconstruct_cli, a_mesh_passes_through_unchanged) {
  const std::string out = (dir / "pass.ply").string();
  const CliRun r = run("reconstruct --in " + niosh_medium + " --kind head --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto a = pipeline::read_scan(niosh_medium), b = pipeline::read_scan(out, {pipeline::Unit::mm});
  EXPECT_EQ(a.soup.polygons, b.soup.polygons);
  ASSERT_EQ(a.soup.points.size(), b.soup.points.size());
  double moved_mm = 0;  // PLY stores float coordinates, as the STL does: read back to the bit
  for (std::size_t i = 0; i < a.soup.points.size(); ++i)
    moved_mm = std::max(moved_mm, std::sqrt(CGAL::squared_distance(a.soup.points[i], b.soup.points[i])));
  EXPECT_EQ(moved_mm, 0.0);
  // in the format --out names (it was PLY bytes whatever the name)
  for (const char* ext : {".off", ".stl"}) {
    const std::string named = (dir / (std::string("pass") + ext)).string();
    ASSERT_EQ(run("reconstruct --in " + niosh_medium + " --kind head --out " + named).code, 0) << ext;
    EXPECT_EQ(pipeline::read_scan(named, {pipeline::Unit::mm}).soup.polygons.size(), a.soup.polygons.size()) << ext;
  }
  EXPECT_EQ(file_text((dir / "pass.off").string()).substr(0, 3), "OFF");
}

TEST(repair_cli, niosh_medium_stl_comes_out_closed_manifold_and_clean) {
  const std::string out = (dir / "niosh_repaired.ply"), report = (dir / "niosh_report.json");
  fs::remove(out);
  const CliRun r = run("repair --in " + niosh_medium + " --kind head --edge 2 --out " + out + " --report " + report);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(file_text(report));
  EXPECT_EQ(j["closed"], true);
  EXPECT_EQ(j["manifold"], true);
  EXPECT_EQ(j["self_intersecting_after"], false);
  EXPECT_EQ(j["boundary_loops_after"], 0);
  // remeshed to 2 mm: mean edge within 25 % (CGAL splits above 4/3 and collapses below 4/5 of it)
  EXPECT_NEAR(j["mean_edge_mm"].get<double>(), 2.0, 0.5);
  // the enclosed volume of the input (divergence theorem over the STL's triangles, which are
  // consistently oriented) changes by < 1 %: smoothing and 2 mm remeshing of a head move the
  // surface by well under 0.1 mm on average, i.e. < 0.3 % of the volume-to-area ratio (~20 mm)
  const auto in = pipeline::read_scan(niosh_medium);
  double vol = 0;
  for (const auto& f : in.soup.polygons) {
    const auto &a = in.soup.points[f[0]], &b = in.soup.points[f[1]], &c = in.soup.points[f[2]];
    vol += CGAL::determinant(a - CGAL::ORIGIN, b - CGAL::ORIGIN, c - CGAL::ORIGIN) / 6.0;
  }
  EXPECT_NEAR(j["volume_mm3"].get<double>(), std::abs(vol), 0.01 * std::abs(vol));
  EXPECT_TRUE(fs::exists(out));
}

// The same scan gives the same bytes whatever the process's heap layout. glibc's tunables move
// the allocations: with mmap_threshold=4096 every block above 4 KB gets its own mapping.
void expect_same_bytes_under_other_heaps(const std::string& scan, const std::string& kind) {
  std::string first;
  for (const std::string env : {"", "GLIBC_TUNABLES=glibc.malloc.mmap_threshold=4096",
                                "GLIBC_TUNABLES=glibc.malloc.top_pad=100000000"}) {
    SCOPED_TRACE(env);
    const std::string out = (dir / ("heap_layout_" + kind + ".ply")).string();
    fs::remove(out);
    const CliRun r = run("reconstruct --in " + scan + " --kind " + kind + " --out " + out, env);
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string bytes = file_text(out);
    ASSERT_GT(bytes.size(), 100000u);
    if (first.empty()) first = bytes;
    EXPECT_TRUE(bytes == first) << "another mesh than without tunables";
  }
}

// Before the contouring's triangulation had time-stamped handles (reconstruct.cpp, Time_stamped)
// this 60,000-point scan gave three different meshes under these three layouts; the surface
// mesher walked sets of handles in address order.
TEST(reconstruct_cli, output_does_not_depend_on_the_heap_layout) {
  const std::string scan = (dir / "niosh60k.ply").string();
  ASSERT_EQ(run("generate_scan --from-mesh " + niosh_medium + " --points 60000 --seed 3 --out " + scan).code, 0);
  expect_same_bytes_under_other_heaps(scan, "head");
}

// Before advancing front (the cups' method) had time-stamped handles and sorted triangles, this
// cup gave 43,562 or 43,560 triangles under these layouts, and the same triangles in other orders
// under longer file names; the repaired cup followed (area 15578.69 vs 15578.98 mm2).
TEST(reconstruct_cli, cup_output_does_not_depend_on_the_heap_layout) {
  const std::string scan = (dir / "onesize.ply").string();
  ASSERT_EQ(run("generate_scan --kind respirator --id onesize --params " + std::string(SOURCE_DIR) +
                "/data/generator/respirators.json --seed 1 --out " + scan).code, 0);
  expect_same_bytes_under_other_heaps(scan, "respirator");
}

// scripts/plot_slice.py, with which the README's slices were drawn: the slice through NIOSH
// medium's neck lip has the reference in its window and gives a PNG; a missing mesh gives one
// line naming it, a non-zero exit and no PNG.
TEST(plot_slice_script, draws_the_niosh_lip_and_rejects_a_missing_mesh) {
  fs::create_directories(dir);
  const std::string script = std::string(SYSTEM_PYTHON) + " " + SOURCE_DIR + "/scripts/plot_slice.py";
  const std::string png = (dir / "lip.png").string(), out = (dir / "plot_slice.txt").string();
  const std::string args = " --axis x --at 1.0 --window -172 -150 -125 -103 --out " + png + " ";
  ASSERT_EQ(run_command(script + args + niosh_medium + " > " + out + " 2>&1"), 0) << file_text(out);
  EXPECT_NE(file_text(out).find("NIOSH_medium_20k.stl: "), std::string::npos) << file_text(out);
  EXPECT_EQ(file_text(out).find(": 0 inside the window"), std::string::npos) << file_text(out);
  const std::string bytes = file_text(png);
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  fs::remove(png);
  EXPECT_GT(run_command(script + args + (dir / "nope.stl").string() + " > " + out + " 2>&1"), 0);
  const std::string err = file_text(out);
  EXPECT_NE(err.find("nope.stl"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_FALSE(fs::exists(png));
  // meshio 5.0 prints two lines and calls sys.exit on a text file named .ply; still one line.
  const std::string text = (dir / "text.ply").string();
  std::ofstream(text) << "this is not a mesh\n";
  EXPECT_GT(run_command(script + args + text + " > " + out + " 2>&1"), 0);
  const std::string text_err = file_text(out);
  EXPECT_NE(text_err.find("plot_slice: " + text + ": cannot read"), std::string::npos) << text_err;
  EXPECT_EQ(std::count(text_err.begin(), text_err.end(), '\n'), 1) << text_err;
  EXPECT_FALSE(fs::exists(png));
}
