#pragma once
/// The check that the cheeks of an aligned head are on their own sides: align's frame puts the
/// subject's left at +x. Labels swapped by hand were fitted, layered and assembled with the left
/// cheek on the right, exit 0. fit checks its parts (face labels), layers its groups.
#include <cmath>
#include <string>

#include "pipeline/error.h"

namespace pipeline {

/// The left cheek's mean x above 0 and the right cheek's below.
///
/// @param[in] file             named in the message
/// @param[in] label_kind       how the file labels its faces: "part" or "group"
/// @param[in] left_mean_x_mm   mean x of the left cheek's vertices [mm]; NaN: no left cheek, not checked
/// @param[in] right_mean_x_mm  the same for the right cheek
/// @throws Error(bad_input) "<file>: part left_cheek lies at mean x = -40 mm, on the subject's
///         right (+x is the left in align's frame): cheek labels swapped?"
inline void require_cheeks_on_their_sides(const std::string& file, const std::string& label_kind, double left_mean_x_mm,
                                          double right_mean_x_mm) {
  const auto check = [&](const char* cheek, double x_mm, bool left) {
    if (std::isnan(x_mm) || (left ? x_mm > 0 : x_mm < 0)) return;
    throw bad_input(file, label_kind + " " + cheek + " lies at mean x = " + format_number(x_mm) + " mm, on the subject's " +
                              (left ? "right" : "left") + " (+x is the left in align's frame): cheek labels swapped?");
  };
  check("left_cheek", left_mean_x_mm, true);
  check("right_cheek", right_mean_x_mm, false);
}

}  // namespace pipeline
