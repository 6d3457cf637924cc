// Tests of layering::segment_head and the `segment` command line, on the NIOSH medium headform
// with the hand-picked landmarks fixture (niosh_medium_landmarks.json, see
// make_niosh_medium_landmarks.py).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "layering/internal/segment_landmarks.h"
#include "layering/segment.h"
#include "pipeline/error.h"
#include "pipeline/read_scan.h"
#include "../niosh_medium_ply.h"

namespace fs = std::filesystem;

namespace {

const std::string fixture = std::string(SOURCE_DIR) + "/tests/segment/niosh_medium_landmarks.json";

// Converted once per test binary.
std::string niosh_medium_ply() {
  static const std::string path =
      ::niosh_medium_ply(fs::temp_directory_path() / ("segment_test_" + std::to_string(::getpid())));
  return path;
}

int run(const std::string& args) {
  const int rc = std::system((std::string(BIN_DIR) + "/segment " + args + " 2>/dev/null").c_str());
  return WEXITSTATUS(rc);
}

}  // namespace

TEST(segment_head, niosh_medium_face_parts_are_disks) {
  const std::string ply = niosh_medium_ply();
  ASSERT_FALSE(ply.empty());
  pipeline::SurfaceMesh mesh = pipeline::read_surface_mesh(ply);
  const auto stats = layering::segment_head(mesh, layering::internal::read_segment_landmarks(fixture));
  ASSERT_EQ(stats.size(), 5u);
  for (const auto& s : stats) {
    SCOPED_TRACE(layering::part_name(s.label));
    // A disk: Euler characteristic 1 and one boundary curve (the closed head minus the face
    // region is a disk too).
    EXPECT_EQ(s.euler, 1);
    EXPECT_EQ(s.boundary_loops, 1);
    EXPECT_GT(s.area_mm2, 3000.0);  // no face part degenerate (a cheek is ~100 cm²)
  }
  // Parts cover the whole surface: their areas add up to the head's area (cuts add no area).
  double total = 0;
  for (const auto& s : stats) total += s.area_mm2;
  EXPECT_NEAR(total, 167890.0, 167890.0 * 0.01);  // area of NIOSH medium measured with meshio
}

TEST(segment_head, cheek_areas_symmetric_on_a_symmetric_head) {
  // NIOSH medium is symmetric about x = 0 to 1.6 mm mean point distance from its mirror image;
  // the cut fields are mirror-symmetric, so the cheek areas may differ only by the head's own
  // asymmetry: < 5 % (issue 3).
  pipeline::SurfaceMesh mesh = pipeline::read_surface_mesh(niosh_medium_ply());
  const auto s = layering::segment_head(mesh, layering::internal::read_segment_landmarks(fixture));
  const double l = s[layering::left_cheek].area_mm2, r = s[layering::right_cheek].area_mm2;
  EXPECT_LT(std::abs(l - r) / (0.5 * (l + r)), 0.05);
}

TEST(segment_cli, writes_labelled_ply_and_rejects_bad_input) {
  const std::string ply = niosh_medium_ply();
  const std::string out = fs::path(ply).parent_path() / "segmented.ply";
  EXPECT_EQ(run("--in " + ply + " --landmarks " + fixture + " --out " + out), 0);
  ASSERT_TRUE(fs::exists(out));
  const pipeline::SurfaceMesh seg = pipeline::read_surface_mesh(out);
  EXPECT_EQ(layering::part_stats(seg, layering::chin).euler, 1);  // "part" read back as f:part
  const std::string bad = fs::path(ply).parent_path() / "bad.ply";
  EXPECT_EQ(run("--in " + ply + " --out " + bad), 1);  // no landmarks: usage
  EXPECT_EQ(run("--in " + ply + " --landmarks /nonexistent.json --out " + bad), 2);
  EXPECT_EQ(run("--in /nonexistent.ply --landmarks " + fixture + " --out " + bad), 2);
  EXPECT_EQ(run("--in " + ply + " --landmarks " + fixture + " --kind hat --out " + bad), 1);
  EXPECT_FALSE(fs::exists(bad));
}
