// align under more random poses (slow): NIOSH heads and respirator parts, and the generated
// headforms when present in the build (generate_scan --kind head --clean-mesh).
#include <gtest/gtest.h>

#include "align_helpers.h"

using namespace align_test;

TEST(align, recovers_the_frame_under_five_more_poses) {
  struct C { const char* file; scan2cad::AlignKind kind; };
  for (const C& c : {C{"headforms/NIOSH_medium_20k.stl", scan2cad::AlignKind::head},
                     C{"headforms/NIOSH_large_20k.stl", scan2cad::AlignKind::head},
                     C{"respirator-parts/Flex_Face_Seal_v9-M.stl", scan2cad::AlignKind::respirator},
                     C{"respirator-parts/Conforming_Invert_M.stl", scan2cad::AlignKind::respirator}}) {
    const double expected = c.kind == scan2cad::AlignKind::head ? 250.0 : 130.0;
    const auto mesh = scan2cad::load_surface_any_unit(data(c.file), expected);
    scan2cad::AlignOptions opt;
    opt.kind = c.kind;
    const auto ref = scan2cad::align(mesh, opt);
    for (unsigned seed = 10; seed < 15; ++seed) {
      const Eigen::Matrix4d G = random_pose(seed);
      const auto got = scan2cad::align(posed_in_metres(mesh, G, "slow", expected, seed), opt);  // own sampling per seed
      double angle, offset;
      frame_error(got.transform * G, ref.transform, angle, offset);
      std::printf("%s seed %u: %.3f deg, %.3f mm\n", c.file, seed, angle, offset);
      EXPECT_LT(angle, 2.0) << c.file << " seed " << seed;  // issue: 2° and 2 mm
      EXPECT_LT(offset, 2.0) << c.file << " seed " << seed;
    }
  }
}
