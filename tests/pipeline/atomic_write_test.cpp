#include <gtest/gtest.h>

#include <filesystem>

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;

TEST(write_atomic, writes_complete_file_and_creates_directories) {
  const fs::path dir = scratch_dir() / "atomic" / "sub";
  fs::remove_all(dir.parent_path());
  const std::string path = (dir / "out.txt").string();
  pipeline::write_text_atomic(path, "hello");
  EXPECT_EQ(pipeline::read_text(path), "hello");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(write_atomic, failed_writer_leaves_no_file_and_keeps_old_one) {
  const fs::path dir = scratch_dir() / "atomic_fail";
  fs::remove_all(dir);
  const std::string path = (dir / "out.txt").string();
  EXPECT_THROW(pipeline::write_atomic(path, [](const std::string& tmp) {
                 pipeline::write_text_atomic(tmp, "half");
                 throw pipeline::algorithm_failed("x", "boom");
               }),
               pipeline::Error);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
  pipeline::write_text_atomic(path, "old");
  EXPECT_THROW(pipeline::write_atomic(path, [](const std::string&) { throw std::runtime_error("x"); }),
               std::runtime_error);
  EXPECT_EQ(pipeline::read_text(path), "old");
}

// A stage's outputs are written all or none: when a later write fails, the files the earlier ones
// wrote are removed (repair's mesh stayed when its report could not be written); an output not
// requested ("" path) is skipped.
TEST(write_all_or_none, a_failed_write_removes_the_ones_before_it) {
  const fs::path dir = scratch_dir() / "all_or_none";
  fs::remove_all(dir);
  const std::string a = (dir / "a.txt").string(), b = (dir / "b.txt").string(), c = (dir / "c.txt").string();
  bool skipped_ran = false;
  EXPECT_THROW(pipeline::write_all_or_none({{a, [&] { pipeline::write_text_atomic(a, "a"); }},
                                            {"", [&] { skipped_ran = true; }},
                                            {b, [&] { pipeline::write_text_atomic(b, "b"); }},
                                            {c, [&] { throw pipeline::io_failed(c, "disk full"); }}}),
               pipeline::Error);
  EXPECT_FALSE(skipped_ran);
  EXPECT_FALSE(fs::exists(a));
  EXPECT_FALSE(fs::exists(b));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
  pipeline::write_all_or_none({{a, [&] { pipeline::write_text_atomic(a, "a"); }}, {"", [] {}},
                               {b, [&] { pipeline::write_text_atomic(b, "b"); }}});
  EXPECT_EQ(pipeline::read_text(a) + pipeline::read_text(b), "ab");
}
