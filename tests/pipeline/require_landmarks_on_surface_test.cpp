// pipeline::require_landmarks_on_surface: the check that a landmarks file belongs to the head it is
// used with (landmarks --user, segment), on a 100 mm square where every distance is exact.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "pipeline/error.h"
#include "pipeline/require_landmarks_on_surface.h"
#include "../bad_input_message.h"

namespace {

pipeline::SurfaceMesh square_100mm() {
  pipeline::SurfaceMesh m;
  const auto a = m.add_vertex({-50, -50, 0}), b = m.add_vertex({50, -50, 0}), c = m.add_vertex({50, 50, 0}),
             d = m.add_vertex({-50, 50, 0});
  m.add_face(a, b, c);
  m.add_face(a, c, d);
  return m;
}

std::map<std::string, pipeline::Landmark> on_square(double menton_z) {
  std::map<std::string, pipeline::Landmark> lm;
  lm["sellion"].position = {0, 30, 0};
  lm["menton"].position = {0, -30, menton_z};
  lm["zygion_left"].position = {45, 0, -3};
  return lm;
}

}  // namespace

TEST(require_landmarks_on_surface, names_the_first_landmark_too_far_and_by_how_much) {
  const auto square = square_100mm();
  const std::string path = "/data/user.json";
  auto message = [&](const std::map<std::string, pipeline::Landmark>& lm, double max_mm = 10) {
    return bad_input_message([&] { pipeline::require_landmarks_on_surface(lm, square, path, max_mm); }, path);
  };
  EXPECT_EQ(message(on_square(10)), "no error");  // the limit itself is allowed
  EXPECT_EQ(message(on_square(12)),
            "landmark menton is 12 mm from the head surface, expected <= 10 mm (same frame as the aligned head?)");
  EXPECT_EQ(message(on_square(-12)).rfind("landmark menton is 12 mm", 0), 0u);  // either side
  EXPECT_EQ(message(on_square(0), 2.5),
            "landmark zygion_left is 3 mm from the head surface, expected <= 2.5 mm (same frame as the aligned head?)");
  // beyond the square's edge the distance is to the edge, not to the plane
  auto outside = on_square(0);
  outside["pronasale"].position = {0, 59, 12};  // 9 mm past the edge, 12 above: 15 mm
  EXPECT_EQ(message(outside).rfind("landmark pronasale is 15 mm from", 0), 0u);
  EXPECT_EQ(message({}), "no error");
  EXPECT_EQ(message(on_square(0)), "no error");
  EXPECT_EQ(bad_input_message([&] { pipeline::require_landmarks_on_surface(on_square(0), pipeline::SurfaceMesh(), path); },
                              path),
            "no surface to check the landmarks against");
}
