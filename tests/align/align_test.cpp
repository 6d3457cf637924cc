// align on the real NIOSH headforms and respirator parts, given in random poses and in metres.
#include <gtest/gtest.h>

#include "align_helpers.h"

using namespace align_test;

namespace {

// Aligns the original and a posed copy; the frames must agree. Tolerance from the issue:
// 2° and 2 mm. The symmetry ICP alone reaches ~0.01°; the rest is the face-axis search.
void expect_pose_recovered(const std::string& file, scan2cad::AlignKind kind, unsigned seed, bool check_full = true) {
  const double expected = kind == scan2cad::AlignKind::head ? 250.0 : 130.0;
  const auto mesh = scan2cad::load_surface_any_unit(data(file), expected);
  scan2cad::AlignOptions opt;
  opt.kind = kind;
  const auto ref = scan2cad::align(mesh, opt);
  const Eigen::Matrix4d G = random_pose(seed);
  const auto posed = posed_in_metres(mesh, G, "posed_" + std::to_string(seed), expected);
  const auto got = scan2cad::align(posed, opt);
  const Eigen::Matrix4d T = got.transform * G;  // original → frame, through the posed copy
  double angle, offset;
  frame_error(T, ref.transform, angle, offset);
  std::printf("%s seed %u: frame error %.3f deg, %.3f mm\n", file.c_str(), seed, angle, offset);
  if (check_full) {
    EXPECT_LT(angle, 2.0);
    EXPECT_LT(offset, 2.0);
  } else {
    // Symmetry plane only: its normal (row x) and offset.
    const Eigen::Vector3d a = T.block<1, 3>(0, 0).transpose(), b = ref.transform.block<1, 3>(0, 0).transpose();
    EXPECT_LT(std::acos(std::min(1.0, std::abs(a.dot(b)))) * 180.0 / M_PI, 2.0);
  }
}

}  // namespace

TEST(align, niosh_medium_in_a_random_pose_in_metres_recovers_the_frame) {
  expect_pose_recovered("headforms/NIOSH_medium_20k.stl", scan2cad::AlignKind::head, 1);
}

TEST(align, niosh_large_in_a_random_pose_in_metres_recovers_the_frame) {
  expect_pose_recovered("headforms/NIOSH_large_20k.stl", scan2cad::AlignKind::head, 2);
}

// NIOSH files are already roughly in the paper's frame (SOURCES.md: y up, face toward +z, x
// lateral): the transform must be near the identity, which checks the signs (left/right, up,
// face). 10° allows for the profile-line pitch convention; the 2 symmetric axes must be ≤ 1°.
TEST(align, niosh_heads_keep_their_upright_frame) {
  for (const char* f : {"headforms/NIOSH_medium_20k.stl", "headforms/NIOSH_large_20k.stl"}) {
    const auto mesh = scan2cad::load_surface_any_unit(data(f), 250.0);
    const auto r = scan2cad::align(mesh, {});
    double angle, offset;
    frame_error(r.transform, Eigen::Matrix4d::Identity(), angle, offset);
    EXPECT_LT(angle, 10.0) << f;
    EXPECT_GT(r.transform(0, 0), std::cos(M_PI / 180.0)) << f << ": +x stays the subject's left";
    EXPECT_LT(r.symmetry_rms_mm, 0.5) << f;
  }
}

TEST(align, respirator_parts_in_a_random_pose_recover_the_frame) {
  expect_pose_recovered("respirator-parts/Flex_Face_Seal_v9-M.stl", scan2cad::AlignKind::respirator, 3);
  expect_pose_recovered("respirator-parts/Conforming_Invert_M.stl", scan2cad::AlignKind::respirator, 4);
}
