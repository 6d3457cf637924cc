#include <gtest/gtest.h>

#include <cmath>

#include "pipeline/error.h"
#include "pipeline/units.h"

using pipeline::Unit;

TEST(detect_unit, recognises_a_head_in_mm_cm_and_m) {
  EXPECT_EQ(pipeline::detect_unit(285.7, 250, "h"), Unit::mm);
  EXPECT_EQ(pipeline::detect_unit(28.57, 250, "h"), Unit::cm);
  EXPECT_EQ(pipeline::detect_unit(0.2857, 250, "h"), Unit::m);
  EXPECT_EQ(pipeline::detect_unit(120, 130, "r"), Unit::mm);
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
