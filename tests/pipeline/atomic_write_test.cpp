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
