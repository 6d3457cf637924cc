#include <gtest/gtest.h>

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "pipeline/error.h"
#include "pipeline/require_affordable_edge.h"
#include "pipeline/surface_mesh.h"
#include "pipeline/units.h"
#include "../bad_input_message.h"

using pipeline::Unit;

TEST(detect_unit, recognises_a_head_in_mm_cm_and_m) {
  EXPECT_EQ(pipeline::detect_unit(285.7, 250, "h"), Unit::mm);
  EXPECT_EQ(pipeline::detect_unit(28.57, 250, "h"), Unit::cm);
  EXPECT_EQ(pipeline::detect_unit(0.2857, 250, "h"), Unit::m);
  EXPECT_EQ(pipeline::detect_unit(120, 130, "r"), Unit::mm);
}

// cm and inches are 2.54 apart: NIOSH medium in inches (11.25) is a plausible 112.5 mm "head" in
// cm and was taken as one. A cm size under 0.6 of the expected one, where inches give a plausible
// size, is now refused with both readings; a real head or respirator in cm still reads as cm.
TEST(detect_unit, a_size_that_may_be_cm_or_inches_is_refused_not_guessed) {
  const std::string head_in_inches = bad_input_message([] { pipeline::detect_unit(285.7 / 25.4, 250, "h.ply"); }, "h.ply");
  EXPECT_EQ(head_in_inches, "cannot tell the length unit: largest extent 11.248 is 112.48 mm in cm, small for an object "
                            "of about 250 mm, or 285.7 mm in inches: force one with --unit cm or --unit in");
  EXPECT_THROW(pipeline::detect_unit(5.0, 130, "r.ply"), pipeline::Error);  // a respirator: 50 mm or 127 mm
  EXPECT_EQ(pipeline::detect_unit(15.1, 250, "h"), Unit::cm);   // 151 mm: a small head's face-only scan
  EXPECT_EQ(pipeline::detect_unit(9.0, 130, "r"), Unit::cm);    // a small respirator, 90 mm
  EXPECT_EQ(pipeline::detect_unit(21.0, 250, "h"), Unit::cm);   // in inches 533 mm, also plausible: cm is nearer
}

// No adult head is under 150 mm (0.6 of 250): in mm such a size is another kind of object, such as
// a respirator (107-133 mm) given as a head, which went through reconstruct and repair.
TEST(detect_unit, a_head_smaller_than_any_adults_is_refused_in_mm_and_m) {
  const std::string cup_as_head = bad_input_message([] { pipeline::detect_unit(111.8, 250, "r.ply"); }, "r.ply");
  EXPECT_EQ(cup_as_head, "largest extent 111.8 mm, under 0.6 of an object of about 250 mm: an object of "
                         "another kind (see --kind), or in another unit (see --unit)? align refuses an object of "
                         "that size");
  const std::string in_m = bad_input_message([] { pipeline::detect_unit(0.1118, 250, "r.ply"); }, "r.ply");
  EXPECT_NE(in_m.find("largest extent 0.1118 is 111.8 mm in m, under 0.6"), std::string::npos) << in_m;
  EXPECT_EQ(pipeline::detect_unit(151, 250, "h"), Unit::mm);  // a small head's face-only scan
  EXPECT_EQ(pipeline::detect_unit(79, 130, "r"), Unit::mm);   // just over 0.6 of a respirator's 130 mm
  EXPECT_THROW(pipeline::detect_unit(77, 130, "r"), pipeline::Error);
}

TEST(detect_unit, rejects_sizes_no_unit_explains) {
  EXPECT_THROW(pipeline::detect_unit(2.0e6, 250, "h"), pipeline::Error);
  EXPECT_THROW(pipeline::detect_unit(1.0e-5, 250, "h"), pipeline::Error);
  EXPECT_THROW(pipeline::detect_unit(0, 250, "h"), pipeline::Error);
  EXPECT_THROW(pipeline::detect_unit(std::nan(""), 250, "h"), pipeline::Error);
}

TEST(parse_unit, round_trips_names) {
  for (auto n : {"auto", "mm", "cm", "m", "in"}) EXPECT_EQ(pipeline::unit_name(pipeline::parse_unit(n)), n);
  EXPECT_THROW(pipeline::parse_unit("furlong"), pipeline::Error);
  EXPECT_DOUBLE_EQ(pipeline::mm_per_unit(Unit::inch), 25.4);
}

TEST(describe_unit, names_the_unit_how_it_was_chosen_and_the_size_it_gives) {
  EXPECT_EQ(pipeline::describe_unit(pipeline::Unit::cm, true, 112.54, "head", 250.0),
            "unit cm (detected, --unit forces one): largest extent 112.5 mm (a head is about 250)");
  EXPECT_EQ(pipeline::describe_unit(pipeline::Unit::inch, false, 285.7, "respirator", 130.0),
            "unit in (forced): largest extent 285.7 mm (a respirator is about 130)");
}

// One stray point or speck of debris a metre off made a head 4.4 m across: refused as no unit,
// and refused again with --unit mm ("its largest extent is 4386 mm"). A few far points (up to
// 0.5 % at each end of an axis) no longer count; without them the extent is the box's, exactly.
TEST(extent_without_far_points, a_few_far_points_do_not_count) {
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) points.push_back({5.0 * i, 5.0 * j, 0.25 * (i + j)});  // 100 x 100 x 10 mm
  EXPECT_EQ(pipeline::extent_without_far_points(points), 100.0);
  points.push_back({0, 0, 1200});  // a stray return a metre off, beside 441 points
  EXPECT_EQ(pipeline::largest_extent(points), 1200.0);
  EXPECT_EQ(pipeline::extent_without_far_points(points), 100.0);
  for (int k = 1; k <= 6; ++k) points.push_back({-1500.0 * k, 0, 0});  // 7 of 448: more than 0.5 %
  EXPECT_GT(pipeline::extent_without_far_points(points), 4000.0);
  EXPECT_EQ(pipeline::extent_without_far_points(std::vector<std::array<double, 3>>{}), 0.0);
}

// Stages after align read mm only: a head written in m, cm or inches is bad input naming the
// file; the NIOSH heads (largest extent 286 mm), a small respirator (~90 mm) and a large head
// pass. The window is detect_unit's: a factor 4 either way of the object's real size.
TEST(require_mm, rejects_a_head_in_m_cm_or_inches_and_names_the_file) {
  EXPECT_NO_THROW(pipeline::require_mm("h.ply", 285.7, "head"));
  EXPECT_NO_THROW(pipeline::require_mm("h.ply", 400, "head"));
  EXPECT_NO_THROW(pipeline::require_mm("r.msh", 90, "respirator"));
  for (double extent : {0.2857, 28.57, 285.7 / 25.4, 285.7 * 10, 0.0, std::nan("")}) {
    const std::string message = bad_input_message([&] { pipeline::require_mm("h.ply", extent, "head"); }, "h.ply");
    EXPECT_EQ(message.rfind("largest extent ", 0), 0u) << extent << " mm: " << message;
    EXPECT_NE(message.find("a head is about 250 mm"), std::string::npos) << message;
  }
  EXPECT_THROW(pipeline::require_mm("r.msh", 28.57, "respirator"), pipeline::Error);
  // straps are sized like the head they span, but are named as straps (assemble said "a head")
  EXPECT_NE(bad_input_message([] { pipeline::require_mm("s.msh", 2.857, "head", "head's strap set"); }, "s.msh")
                .find("but a head's strap set is about 250 mm"),
            std::string::npos);
  EXPECT_THROW(pipeline::expected_extent_mm("hat"), pipeline::Error);
}

// align and landmarks take one whole surface as a head or a respirator: sizes outside 0.6-1.6
// times the kind's are refused (a head aligned as a respirator, a respirator given to landmarks,
// a vertex 3 m off).
TEST(require_real_size, refuses_sizes_no_head_or_respirator_has) {
  EXPECT_NO_THROW(pipeline::require_real_size("h.ply", 285.7, "head"));
  EXPECT_NO_THROW(pipeline::require_real_size("r.ply", 111.8, "respirator"));
  EXPECT_EQ(bad_input_message([] { pipeline::require_real_size("h.ply", 288.44, "respirator"); }, "h.ply"),
            "it spans 288.4 mm, over the 208 mm of the largest respirator: a vertex far off (repair removes spikes and "
            "debris), or an object of another kind (see --kind)?");
  EXPECT_EQ(bad_input_message([] { pipeline::require_real_size("r.ply", 111.8, "head", false); }, "r.ply"),
            "it spans 111.8 mm, under the 150 mm of the smallest head: an object other than a head?");
  EXPECT_THROW(pipeline::require_real_size("h.ply", 3086.4, "head"), pipeline::Error);
  EXPECT_THROW(pipeline::require_real_size("h.ply", std::nan(""), "head"), pipeline::Error);
}

TEST(largest_extent, of_cgal_points_and_eigen_vectors) {
  const std::vector<pipeline::Point> p = {{0, 0, 0}, {3, -5, 1}, {1, 2, 2}};
  EXPECT_DOUBLE_EQ(pipeline::largest_extent(p), 7.0);
  const std::vector<Eigen::Vector3d> e = {{0, 0, 0}, {3, -1, 9}};
  EXPECT_DOUBLE_EQ(pipeline::largest_extent(e), 9.0);
  EXPECT_DOUBLE_EQ(pipeline::largest_extent(std::vector<pipeline::Point>{}), 0.0);
}

// Density in g/mm³: the paper's g/cm³ (1.2 for skin) and kg/m³ (1200) are a thousand and a
// million times too large, t/mm³ (1.2e-9, LS-DYNA's mm-s-t system) a million times too small.
TEST(why_material_unusable, accepts_the_paper_materials_and_names_a_unit_slip) {
  EXPECT_EQ(pipeline::why_material_unusable(1.2e-3, 0.6, 0.45), "");   // skin
  EXPECT_EQ(pipeline::why_material_unusable(4.5e-3, 1000, 0.3), "");   // bone
  EXPECT_EQ(pipeline::why_material_unusable(1e-3, 0.015, 0.48), "");   // fat
  for (const double wrong : {1.2, 1200.0, 1.2e-9})
    EXPECT_EQ(pipeline::why_material_unusable(wrong, 0.6, 0.45).rfind("density " + pipeline::format_number(wrong) +
                                                                          " g/mm³ is outside [1e-06, 0.1]",
                                                                      0),
              0u)
        << wrong;
  EXPECT_EQ(pipeline::why_material_unusable(0, 0.6, 0.45), "density must be > 0");
  EXPECT_EQ(pipeline::why_material_unusable(std::nan(""), 0.6, 0.45), "density must be > 0");
  EXPECT_EQ(pipeline::why_material_unusable(1e-3, std::numeric_limits<double>::infinity(), 0.45),
            "E must be > 0 and finite [MPa]");
  EXPECT_EQ(pipeline::why_material_unusable(1e-3, 0, 0.45), "E must be > 0 and finite [MPa]");
  EXPECT_EQ(pipeline::why_material_unusable(1e-3, 1e9, 0.3), "E 1e+09 MPa is stiffer than any solid (at most 2e+06): give it in MPa");
  EXPECT_EQ(pipeline::why_material_unusable(4.5e-3, 2e5, 0.3), "");  // steel
  EXPECT_EQ(pipeline::why_material_unusable(1e-3, 0.6, 0.5), "nu must be in [0, 0.5)");
  EXPECT_EQ(pipeline::why_material_unusable(1e-3, 0.6, -0.1), "nu must be in [0, 0.5)");
}

// pipeline::require_affordable_edge on a 100 mm square (10,000 mm2): an equilateral triangle of
// edge e covers sqrt(3)/4 e², so the square takes 10,000 / (0.433 e²) of them.
TEST(require_affordable_edge, refuses_an_edge_that_asks_for_too_many_triangles) {
  pipeline::SurfaceMesh square;
  const auto a = square.add_vertex({0, 0, 0}), b = square.add_vertex({100, 0, 0}), c = square.add_vertex({100, 100, 0}),
             d = square.add_vertex({0, 100, 0});
  square.add_face(a, b, c);
  square.add_face(a, c, d);
  EXPECT_NO_THROW(pipeline::require_affordable_edge("--edge", 0.16, square, 1e6));  // ~902,000
  EXPECT_NO_THROW(pipeline::require_affordable_edge("--edge", 0, square, 1e6));     // 0: no remeshing
  EXPECT_EQ(error_message(pipeline::ErrorKind::usage,
                          [&] { pipeline::require_affordable_edge("--size", 0.15, square, 1e6); }),  // ~1,026,000
            "--size 0.15 mm would make ~1e+06 triangles on this 10000 mm2 surface, more than 1 million: choose a longer edge");
}
