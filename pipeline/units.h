#pragma once
/// Length units of scans. The whole project works in mm (DESIGN.md); a scan in another unit is
/// scaled once, when it is read.
#include <string>

namespace pipeline {

enum class Unit { automatic, mm, cm, m, inch };

/// Parses "auto", "mm", "cm", "m" or "in". @throws Error(usage) otherwise.
Unit parse_unit(const std::string& name);
std::string unit_name(Unit u);
/// Millimetres per unit (mm → 1, m → 1000). `automatic` is not a unit: throws.
double mm_per_unit(Unit u);

/// Guesses the unit of an object whose largest bounding-box extent is `extent` (in file
/// units), knowing that it is `expected_mm` long in reality (a head ≈ 250 mm, a respirator
/// ≈ 130 mm). Accepts a unit when the implied size is within a factor 4 of expected_mm.
///
/// @param[in] what  file name for the error message
/// @return mm, cm or m
/// @throws Error(bad_input) when no unit gives a plausible size (e.g. a 3 km "head"), or
///         extent is not positive and finite.
Unit detect_unit(double extent, double expected_mm, const std::string& what);

/// One log line on the unit a file was read in and the size that gives, so that a wrong guess
/// shows: "unit cm (detected, --unit forces one): largest extent 112.5 mm (a head is about 250)".
/// Detection cannot tell cm from inches (a factor 2.54) when both give a plausible size.
/// @param extent_mm  largest bounding-box extent after scaling [mm]
/// @param object     what the file holds ("head", "respirator")
std::string describe_unit(Unit unit, bool detected, double extent_mm, const std::string& object, double expected_mm);

}  // namespace pipeline
