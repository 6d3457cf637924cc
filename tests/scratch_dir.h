// Test helper: one folder for the files a test program writes, cleaned up after it.
//
//   const std::filesystem::path& scratch_dir()
//
// Output: $TMPDIR/<program>_<pid> (e.g. /tmp/fit_test_4242), made empty on the first call.
//   The pid keeps apart the processes ctest runs in parallel (gtest_discover_tests starts one per
//   test) and the test runs of other clones on the same machine.
//   When the program ends it is removed if every test passed. If one failed it is kept and its path
//   printed, so the inputs and outputs of the failing run can be opened; RF_KEEP_TEST_FILES=1 keeps
//   it always. A program that crashes or is killed by ctest's timeout leaves it too, for the same
//   reason.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

namespace test_support {

class ScratchDir {
 public:
  ScratchDir() {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::string program = ec ? std::string("test") : exe.filename().string();
    path_ = std::filesystem::temp_directory_path() / (program + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);  // a folder left by an earlier process with this pid
    std::filesystem::create_directories(path_);
    // gtest owns and deletes the listener; it only flags this object, which outlives the test run.
    ::testing::UnitTest::GetInstance()->listeners().Append(new KeepOnFailure(this));
  }
  ~ScratchDir() {
    const char* keep = std::getenv("RF_KEEP_TEST_FILES");
    if (keep_ || (keep != nullptr && std::string(keep) != "0")) return;
    std::error_code ec;  // a destructor at exit has no one to report to
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  // Flags the folder to be kept when the run had a failure. Not called when gtest only lists the
  // tests (gtest_discover_tests at build time), so that folder is removed.
  class KeepOnFailure : public ::testing::EmptyTestEventListener {
   public:
    explicit KeepOnFailure(ScratchDir* dir) : dir_(dir) {}
    void OnTestProgramEnd(const ::testing::UnitTest& unit_test) override {
      if (unit_test.Passed()) return;
      dir_->keep_ = true;
      std::cerr << "test files kept in " << dir_->path_.string() << "\n";
    }

   private:
    ScratchDir* dir_;
  };

  std::filesystem::path path_;
  bool keep_ = false;
};

}  // namespace test_support

/// The program's scratch folder (see the top of this file); made on the first call.
inline const std::filesystem::path& scratch_dir() {
  static test_support::ScratchDir dir;
  return dir.path();
}

/// Writes `content` as is (binary) to `name` in the scratch folder, making its sub-folders, and
/// returns the file's path: the bad-input files the reader tests feed their readers.
inline std::string scratch_file(const std::string& name, const std::string& content) {
  const std::filesystem::path p = scratch_dir() / name;
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << content;
  return p.string();
}
