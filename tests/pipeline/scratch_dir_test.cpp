// tests/scratch_dir.h, seen from outside the program that uses it: its folder is gone after a run
// whose tests passed and is kept, with its path on stderr, after a run where one failed.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "../file_text.h"
#include "../run_command.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;

namespace {

struct ProbeRun {
  int code = -1;
  std::string folder, err;
};

ProbeRun run_probe(const std::string& env) {
  const fs::path out = scratch_dir() / "probe.out", err = scratch_dir() / "probe.err";
  ProbeRun r;
  r.code = run_command(env + " " + BIN_DIR + "/scratch_dir_probe > " + out.string() + " 2> " + err.string());
  r.err = file_text(err);
  const std::string o = file_text(out);
  const auto at = o.find("scratch ");
  if (at != std::string::npos) r.folder = o.substr(at + 8, o.find('\n', at) - at - 8);
  return r;
}

}  // namespace

TEST(scratch_dir, removed_after_a_passing_run_kept_and_named_after_a_failing_one) {
  const ProbeRun pass = run_probe("");
  EXPECT_EQ(pass.code, 0) << pass.err;
  ASSERT_FALSE(pass.folder.empty()) << pass.err;
  EXPECT_EQ(fs::path(pass.folder).filename().string().rfind("scratch_dir_probe_", 0), 0u) << pass.folder;
  EXPECT_FALSE(fs::exists(pass.folder));

  const ProbeRun fail = run_probe("PROBE_FAIL=1");
  EXPECT_NE(fail.code, 0);
  ASSERT_FALSE(fail.folder.empty()) << fail.err;
  EXPECT_NE(fail.folder, pass.folder);  // one folder per process
  EXPECT_TRUE(fs::exists(fs::path(fail.folder) / "probe.txt"));
  EXPECT_NE(fail.err.find("test files kept in " + fail.folder), std::string::npos) << fail.err;
  fs::remove_all(fail.folder);

  const ProbeRun kept = run_probe("RF_KEEP_TEST_FILES=1");
  EXPECT_EQ(kept.code, 0) << kept.err;
  EXPECT_TRUE(fs::exists(fs::path(kept.folder) / "probe.txt")) << kept.folder;
  fs::remove_all(kept.folder);
}
