// pipeline::Progress: the lines it prints on stderr.
#include <gtest/gtest.h>

#include <string>

#include "pipeline/progress.h"

namespace {
int lines(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n';
  return n;
}
}  // namespace

// Lines are limited to one per interval, with a total or without one: without (0), every
// update() printed a line (sweep R; no stage updated one yet, the first to would have flooded
// stderr). With a total, its last unit is printed whatever the interval.
TEST(progress, updates_are_limited_with_or_without_a_total) {
  testing::internal::CaptureStderr();
  {
    pipeline::Progress unknown("stage", 0, 60.0);
    for (std::size_t k = 1; k <= 100; ++k) unknown.update(k, "reading");
  }
  const std::string without_total = testing::internal::GetCapturedStderr();
  EXPECT_EQ(lines(without_total), 1) << without_total;
  EXPECT_EQ(without_total.rfind("stage: reading 1 elapsed ", 0), 0u) << without_total;
  testing::internal::CaptureStderr();
  {
    pipeline::Progress known("stage", 100, 60.0);
    for (std::size_t k = 1; k <= 100; ++k) known.update(k, "reading");
  }
  const std::string with_total = testing::internal::GetCapturedStderr();
  EXPECT_EQ(lines(with_total), 2) << with_total;  // the first and the last
  EXPECT_NE(with_total.find("stage: reading 100/100 (100%) elapsed "), std::string::npos) << with_total;
}
