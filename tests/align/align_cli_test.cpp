// The align program on bad input: one clear error line, the documented exit code, no output.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "../file_text.h"
#include "../last_line.h"
#include "../run_command.h"
#include "../scratch_dir.h"
#include "pipeline/read_json.h"

namespace fs = std::filesystem;

namespace {

// One folder per process: ctest runs this binary's tests as parallel processes, and a shared
// folder let one test read the other's stderr (repair_cli failed on reconstruct_cli's message).
const fs::path dir = scratch_dir() / "align_cli";

int run(const std::string& args) {
  fs::create_directories(dir);
  return run_command(std::string(BIN_DIR) + "/align " + args + " 2> " + (dir / "err.txt").string());
}

std::string err() { return file_text(dir / "err.txt"); }

std::string outs() { return " --out " + (dir / "a.ply").string() + " --transform " + (dir / "a.json").string(); }

}  // namespace

TEST(align_cli, missing_input_file_exits_2_without_output) {
  fs::remove_all(dir);
  EXPECT_EQ(run("--in " + (dir / "nope.ply").string() + outs()), 2);
  EXPECT_NE(err().find("nope.ply"), std::string::npos) << err();
  EXPECT_FALSE(fs::exists(dir / "a.ply"));
  EXPECT_FALSE(fs::exists(dir / "a.json"));
}

TEST(align_cli, point_cloud_input_exits_2_naming_the_file_and_writes_nothing) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path xyz = dir / "cloud.xyz";
  {
    std::ofstream f(xyz);
    for (int i = 0; i < 200; ++i) f << (i % 10) * 20 << " " << (i / 10) * 10 << " " << (i % 7) << "\n";
  }
  EXPECT_EQ(run("--in " + xyz.string() + outs()), 2);
  // The last line is the error; before it come only the options and progress lines.
  EXPECT_EQ(last_line(err()), "align: " + xyz.string() + ": is a point cloud, expected a surface mesh (run reconstruct and repair first)");
  EXPECT_FALSE(fs::exists(dir / "a.ply"));
  EXPECT_FALSE(fs::exists(dir / "a.json"));
}

TEST(align_cli, unknown_kind_is_a_usage_error) {
  EXPECT_EQ(run("--in x.ply --kind elbow" + outs()), 1);
  EXPECT_NE(err().find("elbow"), std::string::npos) << err();
}

TEST(align_cli, aligns_the_niosh_medium_headform) {
  fs::remove_all(dir);
  EXPECT_EQ(run("--in " + std::string(SHARED_DATA_DIR) + "/headforms/NIOSH_medium_20k.stl --kind head" + outs()), 0) << err();
  EXPECT_TRUE(fs::exists(dir / "a.ply"));
  const std::string json = file_text(dir / "a.json");
  EXPECT_NE(json.find("\"matrix\""), std::string::npos);
}

// A head in inches: the size alone could be cm (a 112 mm head, 2.54x too small but within the
// detection window), which was taken, and align then found no forehead-chin profile (exit 3).
// Now it is refused with both readings (exit 2); --unit in reads it right. An unknown unit is a
// usage error.
TEST(align_cli, unit_option_forces_the_unit_the_size_cannot_tell) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string inches = (dir / "head_in.ply").string();
  const std::string convert = std::string(SYSTEM_PYTHON) + " -c \"import meshio; m = meshio.read('" + SHARED_DATA_DIR +
                              "/headforms/NIOSH_medium_20k.stl'); meshio.write('" + inches +
                              "', meshio.Mesh(m.points / 25.4, m.cells), binary=False)\" 2>/dev/null";
  ASSERT_EQ(std::system(convert.c_str()), 0);
  EXPECT_EQ(run("--in " + inches + outs()), 2) << err();
  EXPECT_NE(err().find(inches + ": cannot tell the length unit: largest extent 11.24"), std::string::npos) << err();
  EXPECT_NE(err().find(" mm in cm, small for an object of about 250 mm, or 285."), std::string::npos) << err();
  ASSERT_EQ(run("--in " + inches + " --unit in" + outs()), 0) << err();
  EXPECT_EQ(pipeline::read_json((dir / "a.json").string()).at("unit_scale_to_mm").get<double>(), 25.4);
  EXPECT_EQ(run("--in " + inches + " --unit m" + outs()), 2);  // ~11 m: no head
  EXPECT_NE(err().find(inches + ": read in m (--unit), its largest extent is 1124"), std::string::npos) << err();
  EXPECT_EQ(run("--in " + inches + " --unit parsec" + outs()), 1);
  EXPECT_NE(err().find("parsec"), std::string::npos) << err();
}

// align takes the whole surface as the object: a head given as a respirator (285.7 mm) was aligned
// as one with exit 0, and a vertex 3 m off a head (the unit is guessed without a few far points)
// ended 5 s later as "cannot tell up from down". Both are refused by their size, with no output.
TEST(align_cli, a_surface_larger_than_its_kind_is_refused) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string stl = std::string(SHARED_DATA_DIR) + "/headforms/NIOSH_medium_20k.stl";
  EXPECT_EQ(run("--in " + stl + " --kind respirator" + outs()), 2);
  EXPECT_EQ(last_line(err()), "align: " + stl + ": it spans 285.7 mm, over the 208 mm of the largest respirator: a vertex far "
                                                 "off (repair removes spikes and debris), or an object of another kind (see --kind)?");
  const std::string spiked = (dir / "spiked.ply").string();
  const std::string convert = std::string(SYSTEM_PYTHON) + " -c \"import meshio; m = meshio.read('" + stl +
                              "'); p = m.points.astype(float); p[0, 2] += 3000; meshio.write('" + spiked +
                              "', meshio.Mesh(p, m.cells), binary=False)\" 2>/dev/null";
  ASSERT_EQ(std::system(convert.c_str()), 0);
  EXPECT_EQ(run("--in " + spiked + outs()), 2);
  EXPECT_NE(last_line(err()).find(spiked + ": it spans 3115.3 mm"), std::string::npos) << err();
  EXPECT_NE(last_line(err()).find(" mm, over the 400 mm of the largest head: a vertex far off"), std::string::npos) << err();
  EXPECT_FALSE(fs::exists(dir / "a.ply"));
  EXPECT_FALSE(fs::exists(dir / "a.json"));
}
