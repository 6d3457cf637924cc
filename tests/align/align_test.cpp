// align on the real NIOSH headforms and respirator parts, given in random poses and in metres.
#include <gtest/gtest.h>

#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/iterator.h>

#include "align_helpers.h"
#include "pipeline/error.h"

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

// A head with a side cut away has no symmetry plane to find the frame from: NIOSH medium with
// everything beyond 30 mm to its left removed was aligned 176 deg off with exit 0 (sweep J; 57 %
// of its surface matched its mirror image). Refused; the whole head matches over 99 %.
TEST(align, a_head_missing_a_side_is_refused) {
  auto mesh = scan2cad::load_surface_any_unit(data("headforms/NIOSH_medium_20k.stl"), 250.0);
  const auto whole = scan2cad::align(mesh, {});
  EXPECT_GT(whole.symmetry_inliers, 0.95);
  scan2cad::apply_transform(mesh, whole.transform);
  std::vector<pipeline::SurfaceMesh::Face_index> left;
  for (auto f : mesh.faces()) {
    double x = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) x += mesh.point(v).x() / 3;
    if (x > 30) left.push_back(f);
  }
  for (auto f : left) CGAL::Euler::remove_face(mesh.halfedge(f), mesh);
  mesh.collect_garbage();
  try {
    scan2cad::align(mesh, {});
    ADD_FAILURE() << "a head missing its left side was aligned";
  } catch (const pipeline::Error& e) {
    EXPECT_EQ(e.kind, pipeline::ErrorKind::algorithm);
    const std::string what = e.what();
    EXPECT_NE(what.find("head: only "), std::string::npos) << what;
    EXPECT_NE(what.find(" % of the surface matches its mirror image across the best symmetry plane"), std::string::npos) << what;
    EXPECT_NE(what.find("is a side of it missing or cut away?"), std::string::npos) << what;
  }
}
