// Makefile.cases as a build system: which stages run when, with stand-in stage programs that
// only write their outputs and log their name, so the dependency graph is tested in seconds.
// What is checked: the 30 cases share the chains of their heads and respirators; a swapped-in
// scan runs in the case's own folder and re-runs even when the scan file is older; a rebuilt
// stage program re-runs exactly its stage and those after it; a failed stage leaves no output,
// nor any made from its old output; nothing runs twice.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../file_text.h"
#include "../run_command.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;

namespace {

const char* const kStages[] = {"generate_scan", "reconstruct", "repair", "align", "landmarks", "segment",
                               "fit", "surface_mesh", "layers", "straps", "assemble", "solve"};

// A temporary BUILD folder whose bin/ holds stand-ins: each writes every file named after
// --out/--report/--transform/--deck1/--deck2, appends "<stage> <first output>" to log.txt, sleeps
// 3 s (after touching BUILD/sleeping) when SLEEP_STAGE names it, and exits 3 after writing when
// FAIL_STAGE names it (a stage that dies after a partial write).
class CasesMake : public ::testing::Test {
 protected:
  void SetUp() override {
    build_ = scratch_dir() / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(build_);
    fs::create_directories(build_ / "bin");
    for (const char* s : kStages) {
      const fs::path p = build_ / "bin" / s;
      std::ofstream(p) << "#!/bin/sh\n"
                          "first=''\n"
                          "while [ $# -gt 0 ]; do\n"
                          "  case \"$1\" in --out|--report|--transform|--deck1|--deck2)\n"
                          "    mkdir -p \"$(dirname \"$2\")\"; echo \"$0 $*\" > \"$2\"; [ -n \"$first\" ] || first=\"$2\";;\n"
                          "  esac; shift\n"
                          "done\n"
                          "echo \"$(basename \"$0\") $first\" >> " << (build_ / "log.txt").string() << "\n"
                          "if [ \"$SLEEP_STAGE\" = \"$(basename \"$0\")\" ]; then touch " << (build_ / "sleeping").string()
                       << "; sleep 3; fi\n"
                          "[ \"$FAIL_STAGE\" = \"$(basename \"$0\")\" ] && exit 3\n"
                          "exit 0\n";
      fs::permissions(p, fs::perms::owner_all);
    }
  }

  // Runs the case rules; returns make's exit status and the lines the stand-ins logged.
  int make(const std::string& args, std::vector<std::string>* ran, const std::string& env = "") {
    fs::remove(build_ / "log.txt");
    const std::string cmd = env + " make --no-print-directory -C " SOURCE_DIR " -f Makefile.cases BUILD=" +
                            build_.string() + " " + args + " > " + (build_ / "make.out").string() + " 2>&1";
    const int code = run_command(cmd);
    ran->clear();
    std::ifstream log(build_ / "log.txt");
    for (std::string line; std::getline(log, line);) ran->push_back(line);
    return code;
  }
  // How many logged lines are stage `stage` writing under `where` (a path fragment).
  static int count(const std::vector<std::string>& ran, const std::string& stage, const std::string& where) {
    int n = 0;
    for (const auto& l : ran) n += l.rfind(stage + " ", 0) == 0 && l.find(where) != std::string::npos;
    return n;
  }
  std::string log_text(const std::vector<std::string>& ran) {
    std::ostringstream s;
    for (const auto& l : ran) s << l << "\n";
    s << "--- make:\n" << file_text(build_ / "make.out");
    return s.str();
  }
  fs::path build_;
};

TEST_F(CasesMake, cases_share_their_head_and_nothing_runs_twice) {
  std::vector<std::string> ran;
  ASSERT_EQ(make("case=medium_onesize", &ran), 0) << log_text(ran);
  EXPECT_EQ(count(ran, "reconstruct", "/heads/medium/"), 1) << log_text(ran);
  EXPECT_EQ(count(ran, "reconstruct", "/respirators/onesize/"), 1);
  EXPECT_EQ(count(ran, "assemble", "/cases/medium_onesize/model.msh"), 1);
  EXPECT_EQ(ran.size(), 2u + 2 * 7 + 1 + 2) << log_text(ran);  // 2 scans, 2 chains of 7, landmarks, straps, assemble
  EXPECT_TRUE(fs::is_symlink(build_ / "cases/medium_onesize/head"));
  EXPECT_TRUE(fs::exists(build_ / "cases/medium_onesize/head/layers.msh"));

  ASSERT_EQ(make("case=medium_onesize", &ran), 0);
  EXPECT_TRUE(ran.empty()) << log_text(ran);

  // Another respirator on the same head: only its chain, its straps and its model.
  ASSERT_EQ(make("case=medium_twosize-s", &ran), 0);
  EXPECT_EQ(count(ran, "reconstruct", "/heads/"), 0) << log_text(ran);
  EXPECT_EQ(count(ran, "landmarks", ""), 0);
  EXPECT_EQ(count(ran, "layers", "/respirators/twosize-s/"), 1);
  EXPECT_EQ(count(ran, "straps", "/cases/medium_twosize-s/"), 1);
  EXPECT_EQ(ran.size(), 1u + 7 + 2) << log_text(ran);
}

TEST_F(CasesMake, a_swapped_in_scan_runs_in_the_case_folder_even_when_older) {
  std::vector<std::string> ran;
  ASSERT_EQ(make("case=medium_onesize", &ran), 0) << log_text(ran);
  const fs::path scan = build_ / "my_head.ply";
  std::ofstream(scan) << "ply\n";
  ASSERT_EQ(std::system(("touch -d 2000-01-01 " + scan.string()).c_str()), 0);  // older than every output

  ASSERT_EQ(make("case=medium_onesize HEADFORM_SCAN=" + scan.string(), &ran), 0) << log_text(ran);
  EXPECT_EQ(count(ran, "reconstruct", "/cases/medium_onesize/head/"), 1) << log_text(ran);
  EXPECT_EQ(count(ran, "reconstruct", "/respirators/"), 0);
  EXPECT_EQ(count(ran, "assemble", "/cases/medium_onesize/"), 1);
  EXPECT_FALSE(fs::is_symlink(build_ / "cases/medium_onesize/head"));
  EXPECT_TRUE(fs::exists(build_ / "heads/medium/layers.msh")) << "the shared head must be untouched";

  // Back to the generated head: the shared chain is still current, so only straps and model.
  ASSERT_EQ(make("case=medium_onesize", &ran), 0);
  EXPECT_TRUE(fs::is_symlink(build_ / "cases/medium_onesize/head"));
  EXPECT_TRUE(fs::exists(build_ / "cases/medium_onesize/head.previous/layers.msh")) << "own-scan results kept";
  EXPECT_EQ(count(ran, "straps", ""), 1) << log_text(ran);
  EXPECT_EQ(count(ran, "assemble", ""), 1);
  EXPECT_EQ(ran.size(), 2u) << log_text(ran);
}

TEST_F(CasesMake, a_rebuilt_stage_reruns_itself_and_what_follows_and_a_failure_leaves_no_output) {
  std::vector<std::string> ran;
  ASSERT_EQ(make("case=small_onesize", &ran), 0) << log_text(ran);
  ASSERT_EQ(std::system(("touch " + (build_ / "bin/fit").string()).c_str()), 0);
  ASSERT_EQ(make("case=small_onesize", &ran), 0);
  for (const char* s : {"fit", "surface_mesh", "layers"}) {
    EXPECT_EQ(count(ran, s, "/heads/small/"), 1) << s << "\n" << log_text(ran);
    EXPECT_EQ(count(ran, s, "/respirators/onesize/"), 1) << s;
  }
  for (const char* s : {"reconstruct", "repair", "align", "landmarks", "segment"}) EXPECT_EQ(count(ran, s, ""), 0) << s;
  EXPECT_EQ(ran.size(), 3u * 2 + 2) << log_text(ran);

  // layers dies after writing: make fails, and neither layers output nor anything after it is left.
  ASSERT_EQ(std::system(("touch " + (build_ / "bin/layers").string()).c_str()), 0);
  EXPECT_NE(make("case=small_onesize", &ran, "FAIL_STAGE=layers"), 0);
  EXPECT_FALSE(fs::exists(build_ / "heads/small/layers.msh") && fs::exists(build_ / "respirators/onesize/layers.msh"))
      << log_text(ran);
  const bool head_failed = !fs::exists(build_ / "heads/small/layers.msh");
  const fs::path failed = head_failed ? build_ / "heads/small" : build_ / "respirators/onesize";
  EXPECT_FALSE(fs::exists(failed / "layers.msh"));
  EXPECT_TRUE(fs::exists(failed / "surface.msh"));
  EXPECT_EQ(count(ran, "straps", ""), 0);
  // nor the case's model made by the older layers (it was left for solve to take)
  for (const char* stale : {"straps.msh", "model.msh", "stage1.json", "stage2.json"})
    EXPECT_FALSE(fs::exists(build_ / "cases/small_onesize" / stale)) << stale << "\n" << log_text(ran);
  // Fixed program: the next run completes the case.
  ASSERT_EQ(make("case=small_onesize", &ran), 0) << log_text(ran);
  EXPECT_TRUE(fs::exists(build_ / "cases/small_onesize/model.msh"));

  // The same from the first stage: a rebuilt generator that fails leaves nothing made from its old scan.
  ASSERT_EQ(std::system(("touch " + (build_ / "bin/generate_scan").string()).c_str()), 0);
  EXPECT_NE(make("case=small_onesize", &ran, "FAIL_STAGE=generate_scan"), 0);
  const bool head_scan_failed = !fs::exists(build_ / "scans/head-small.ply");
  const fs::path chain = head_scan_failed ? build_ / "heads/small" : build_ / "respirators/onesize";
  for (const char* stale : {"reconstructed.ply", "aligned.ply", "layers.msh"})
    EXPECT_FALSE(fs::exists(chain / stale)) << stale << "\n" << log_text(ran);
  EXPECT_FALSE(fs::exists(build_ / "cases/small_onesize/model.msh"));
  ASSERT_EQ(make("case=small_onesize", &ran), 0) << log_text(ran);
  EXPECT_TRUE(fs::exists(build_ / "cases/small_onesize/model.msh"));
}

// Every file and link under the BUILD folder with its size, mtime and link target: what a run
// that must change nothing may not change.
std::string folder_state(const fs::path& root) {
  std::vector<std::string> lines;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it) {
    const fs::path& p = it->path();
    std::string line = p.lexically_relative(root).string();
    if (fs::is_symlink(p)) {
      line += " -> " + fs::read_symlink(p).string();
      it.disable_recursion_pending();
    } else if (fs::is_regular_file(p)) {
      line += " " + std::to_string(fs::file_size(p)) + " " +
              std::to_string(fs::last_write_time(p).time_since_epoch().count());
    }
    if (p.filename() != "log.txt" && p.filename() != "make.out") lines.push_back(line);
  }
  std::sort(lines.begin(), lines.end());
  std::string all;
  for (const auto& l : lines) all += l + "\n";
  return all;
}

// make -n rearranged the case's folders and rewrote inputs.txt while the makefile was read; a
// scan replaced by older content at the same path was taken as up to date; the same file under
// another spelling re-ran everything.
TEST_F(CasesMake, a_dry_run_changes_nothing_and_a_scan_is_known_by_its_content) {
  std::vector<std::string> ran;
  const fs::path scan = build_ / "my_head.ply";
  std::ofstream(scan) << "ply first\n";
  ASSERT_EQ(make("case=medium_onesize HEADFORM_SCAN=" + scan.string(), &ran), 0) << log_text(ran);
  ASSERT_EQ(make("case=medium_onesize", &ran), 0) << log_text(ran);  // back: own head kept as head.previous
  const std::string before = folder_state(build_);
  ASSERT_EQ(make("-n case=medium_onesize HEADFORM_SCAN=" + scan.string(), &ran), 0) << log_text(ran);
  EXPECT_TRUE(ran.empty()) << log_text(ran);
  EXPECT_EQ(folder_state(build_), before) << log_text(ran);
  // and it lists what a real run would re-run: the case's own chain on that scan (it listed nothing)
  EXPECT_NE(file_text(build_ / "make.out").find("/reconstruct --in " + scan.string()), std::string::npos)
      << file_text(build_ / "make.out");
  EXPECT_NE(file_text(build_ / "make.out").find("/align --in " + (build_ / "cases/medium_onesize/head").string()),
            std::string::npos) << file_text(build_ / "make.out");
  ASSERT_EQ(make("-n case=small_onesize", &ran), 0);
  EXPECT_EQ(folder_state(build_), before) << "a dry run of another case made its folders";
  EXPECT_NE(file_text(build_ / "make.out").find("/reconstruct --in "), std::string::npos)  // it still says what it would run
      << file_text(build_ / "make.out");

  ASSERT_EQ(make("case=medium_onesize HEADFORM_SCAN=" + scan.string(), &ran), 0) << log_text(ran);
  ASSERT_EQ(make("case=medium_onesize HEADFORM_SCAN=" + scan.string(), &ran), 0);
  EXPECT_TRUE(ran.empty()) << log_text(ran);
  // the same file, spelt through a "." folder and a link
  fs::create_directory_symlink(build_, build_.string() + "_link");
  const std::string other_spelling = build_.string() + "_link/./my_head.ply";
  ASSERT_EQ(make("case=medium_onesize HEADFORM_SCAN=" + other_spelling, &ran), 0) << log_text(ran);
  EXPECT_TRUE(ran.empty()) << log_text(ran);
  fs::remove(build_.string() + "_link");
  // other content, with an mtime older than every output
  std::ofstream(scan) << "ply second\n";
  ASSERT_EQ(std::system(("touch -d 2000-01-01 " + scan.string()).c_str()), 0);
  ASSERT_EQ(make("case=medium_onesize HEADFORM_SCAN=" + scan.string(), &ran), 0) << log_text(ran);
  EXPECT_EQ(count(ran, "reconstruct", "/cases/medium_onesize/head/"), 1) << log_text(ran);
  EXPECT_EQ(count(ran, "assemble", "/cases/medium_onesize/"), 1) << log_text(ran);
}

// Each user error stops make before any folder is touched, with one line naming the variable.
TEST_F(CasesMake, bad_variables_stop_before_anything_is_set_up) {
  std::vector<std::string> ran;
  const fs::path scan = build_ / "my_head.ply";
  std::ofstream(scan) << "ply\n";
  ASSERT_EQ(make("case=medium_onesize HEADFORM_SCAN=" + scan.string(), &ran), 0) << log_text(ran);
  ASSERT_EQ(make("case=medium_onesize", &ran), 0);
  ASSERT_TRUE(fs::exists(build_ / "cases/medium_onesize/head.previous/layers.msh"));
  fs::create_directories(build_ / "with space");
  std::ofstream(build_ / "with space/scan.ply") << "ply\n";
  std::ofstream(build_ / "empty.ply").flush();
  const std::string before = folder_state(build_);
  const std::pair<std::string, std::string> refused[] = {
      {"HEADFORM_SCAN=/nonexistent.stl", "HEADFORM_SCAN=/nonexistent.stl: no such file"},
      {"HEADFORM_SCAN=", "HEADFORM_SCAN is empty: give a file, or leave HEADFORM_SCAN out for the default"},
      {"'HEADFORM_SCAN=" + (build_ / "with space/scan.ply").string() + "'", "make cannot take a path with a space"},
      {"HEADFROM_SCAN=" + scan.string(), "unknown variable HEADFROM_SCAN="},
      {"HEADFORM_UNIT=in", "HEADFORM_UNIT=in without HEADFORM_SCAN=: the generated scans are in mm"},
      {"HEADFORM_SCAN=" + scan.string() + " HEADFORM_UNIT=ft", "HEADFORM_UNIT=ft: expected auto, mm, cm, m or in"},
      {"LANDMARKS=/nonexistent.json", "LANDMARKS=/nonexistent.json: no such file"},
      {"LANDMARKS=" + build_.string(), ": is a folder, give a file"},
      {"RESPIRATOR_SCAN=" + (build_ / "empty.ply").string(), "empty.ply: the file is empty"},
      {"HEADFORM_SCAN=/dev/zero", "HEADFORM_SCAN=/dev/zero: not a regular file (a device, pipe or socket)"},  // "empty" before
      {"GAP_MM=abc", "GAP_MM=abc: expected a number in mm"},
      {"STRAP_LENGTH_MM=", "STRAP_LENGTH_MM=: expected a number in mm"},
      {"'BRIDGE_OFFSET_MM=5 6'", "BRIDGE_OFFSET_MM='5 6': expected one number in mm"},
  };
  for (const auto& [args, expected] : refused) {
    EXPECT_NE(make("case=medium_onesize " + args, &ran), 0) << args;
    EXPECT_NE(file_text(build_ / "make.out").find(expected), std::string::npos) << args << "\n" << log_text(ran);
    EXPECT_TRUE(ran.empty()) << args;
    EXPECT_EQ(folder_state(build_), before) << args;
  }
  EXPECT_NE(make("case=../cases/medium_onesize", &ran), 0);
  EXPECT_NE(file_text(build_ / "make.out").find("a case is a file name of data/cases/ without .mk"), std::string::npos);
  // a run on another scan that fails at its first stage leaves an own folder of only inputs.txt;
  // back on the generated head, that folder is removed and head.previous keeps the whole chain
  // (it was replaced by the folder of inputs.txt: sweep J)
  const fs::path scan2 = build_ / "my_other_head.ply";
  std::ofstream(scan2) << "ply other\n";
  EXPECT_NE(make("case=medium_onesize HEADFORM_SCAN=" + scan2.string(), &ran, "FAIL_STAGE=reconstruct"), 0);
  ASSERT_EQ(make("case=medium_onesize", &ran), 0) << log_text(ran);
  EXPECT_TRUE(fs::exists(build_ / "cases/medium_onesize/head.previous/layers.msh")) << log_text(ran);
  EXPECT_TRUE(fs::is_symlink(build_ / "cases/medium_onesize/head"));
  // the case's own landmarks output given back as LANDMARKS (it made a circular rule)
  ASSERT_EQ(make("case=medium_onesize HEADFORM_SCAN=" + scan.string(), &ran), 0);
  const std::string own = (build_ / "cases/medium_onesize/head/landmarks.json").string();
  EXPECT_NE(make("case=medium_onesize HEADFORM_SCAN=" + scan.string() + " LANDMARKS=" + own, &ran), 0);
  EXPECT_NE(file_text(build_ / "make.out").find("is this case's own landmarks output"), std::string::npos)
      << file_text(build_ / "make.out");
}

// BUILD set in the shell for something else moved the whole build there; only make's command line
// sets it now. A dry run, so the source tree's own build folder is only read.
TEST(cases_makefile, build_from_the_environment_is_ignored) {
  const fs::path out = scratch_dir() / "env_build.out";
  const fs::path elsewhere = scratch_dir() / "elsewhere";
  run_command("BUILD=" + elsewhere.string() + " make -n --no-print-directory -C " SOURCE_DIR
              " -f Makefile.cases case=medium_onesize > " + out.string() + " 2>&1");
  const std::string text = file_text(out);
  EXPECT_NE(text.find("outputs in build/cases/medium_onesize/"), std::string::npos) << text;
  EXPECT_EQ(text.find(elsewhere.string()), std::string::npos) << text;
  EXPECT_FALSE(fs::exists(elsewhere));
}

// A misspelt case or a missing scan through the top Makefile is refused when make reads it, before
// the Debian packages are checked or anything is configured or built (it cost the whole install
// and compile).
TEST(cases_makefile, an_unknown_case_or_a_missing_scan_is_refused_before_the_build) {
  const fs::path out = scratch_dir() / "unknown_case.out";
  const fs::path build = scratch_dir() / "unknown_case_build";
  fs::remove_all(build);
  EXPECT_NE(run_command("make --no-print-directory -C " SOURCE_DIR " case=medium_onsize BUILD=" + build.string() +
                        " > " + out.string() + " 2>&1"),
            0);
  const std::string text = file_text(out);
  EXPECT_NE(text.find("unknown case 'medium_onsize': no data/cases/medium_onsize.mk"), std::string::npos) << text;
  EXPECT_EQ(text.find("install-deps"), std::string::npos) << text;
  EXPECT_EQ(text.find("cmake"), std::string::npos) << text;
  EXPECT_FALSE(fs::exists(build));
  // a scan that is not there: the same, before the build
  EXPECT_NE(run_command("make --no-print-directory -C " SOURCE_DIR " case=medium_onesize HEADFORM_SCAN=/nonexistent.ply "
                        "BUILD=" + build.string() + " > " + out.string() + " 2>&1"),
            0);
  EXPECT_NE(file_text(out).find("HEADFORM_SCAN=/nonexistent.ply: no such file"), std::string::npos) << file_text(out);
  EXPECT_FALSE(fs::exists(build));
}

// make -n on a fresh clone (no program built yet) lists every stage's command, as the build that
// `make case=...` runs first makes them all: it listed none and called every stage "not yet part
// of the pipeline". It writes nothing.
TEST(cases_makefile, a_dry_run_before_the_build_lists_every_stage) {
  const fs::path out = scratch_dir() / "fresh_dry.out";
  const fs::path fresh = scratch_dir() / "fresh_build";
  fs::remove_all(fresh);
  fs::create_directories(fresh);
  ASSERT_EQ(run_command("make -n --no-print-directory -C " SOURCE_DIR " -f Makefile.cases case=medium_onesize BUILD=" +
                        fresh.string() + " > " + out.string() + " 2>&1"),
            0)
      << file_text(out);
  const std::string text = file_text(out);
  for (const char* stage : {"generate_scan", "reconstruct", "repair", "align", "landmarks", "segment", "fit",
                            "surface_mesh", "layers", "straps", "assemble"})
    EXPECT_NE(text.find(fresh.string() + "/bin/" + stage + " --"), std::string::npos) << stage << "\n" << text;
  EXPECT_EQ(text.find("not yet part of the pipeline (next): reconstruct"), std::string::npos) << text;
  EXPECT_TRUE(fs::is_empty(fresh));
}

// A landmarks file alone changes nothing before the landmarks stage: the case's own head chain
// starts from the shared aligned head (it re-ran reconstruct, repair and align, ~45 s).
TEST_F(CasesMake, a_landmarks_file_alone_starts_from_the_shared_aligned_head) {
  std::vector<std::string> ran;
  ASSERT_EQ(make("case=medium_onesize", &ran), 0) << log_text(ran);
  const std::string shared = folder_state(build_ / "heads");
  const fs::path landmarks = build_ / "my_landmarks.json";
  std::ofstream(landmarks) << "{}\n";
  ASSERT_EQ(make("case=medium_onesize LANDMARKS=" + landmarks.string(), &ran), 0) << log_text(ran);
  for (const char* s : {"generate_scan", "reconstruct", "repair", "align"}) EXPECT_EQ(count(ran, s, ""), 0) << s << log_text(ran);
  for (const char* s : {"landmarks", "segment", "fit", "surface_mesh", "layers"})
    EXPECT_EQ(count(ran, s, "/cases/medium_onesize/head/"), 1) << s << log_text(ran);
  EXPECT_NE(file_text(build_ / "make.out").find("/bin/segment --in " + (build_ / "heads/medium/aligned.ply").string()),
            std::string::npos)
      << log_text(ran);
  EXPECT_EQ(ran.size(), 7u) << log_text(ran);  // the five, straps, assemble
  EXPECT_EQ(folder_state(build_ / "heads"), shared) << "the shared chain must be untouched";
  ASSERT_EQ(make("case=medium_onesize LANDMARKS=" + landmarks.string(), &ran), 0);
  EXPECT_TRUE(ran.empty()) << log_text(ran);
  ASSERT_EQ(make("case=medium_onesize", &ran), 0);
  EXPECT_EQ(ran.size(), 2u) << log_text(ran);  // straps and assemble on the shared head again
}

// A scan in inches goes through make with HEADFORM_UNIT; when a case's inputs change, what the old
// ones made is removed, so a failed run leaves no model of the previous setup.
TEST_F(CasesMake, a_unit_reaches_reconstruct_and_a_changed_setup_leaves_no_stale_model) {
  std::vector<std::string> ran;
  const fs::path scan = build_ / "my_head.ply";
  std::ofstream(scan) << "ply\n";
  ASSERT_EQ(make("case=medium_onesize HEADFORM_SCAN=" + scan.string() + " HEADFORM_UNIT=in", &ran), 0) << log_text(ran);
  EXPECT_NE(file_text(build_ / "cases/medium_onesize/head/reconstructed.ply").find("--unit in"), std::string::npos);
  ASSERT_TRUE(fs::exists(build_ / "cases/medium_onesize/model.msh"));
  ASSERT_EQ(make("case=medium_onesize HEADFORM_SCAN=" + scan.string() + " HEADFORM_UNIT=in", &ran), 0);
  EXPECT_TRUE(ran.empty()) << log_text(ran);
  EXPECT_NE(make("case=medium_onesize HEADFORM_SCAN=" + scan.string() + " HEADFORM_UNIT=cm", &ran,
                 "FAIL_STAGE=reconstruct"),
            0);
  EXPECT_EQ(count(ran, "reconstruct", "/cases/medium_onesize/head/"), 1) << log_text(ran);
  for (const char* stale : {"head/repaired.ply", "head/layers.msh", "straps.msh", "model.msh", "stage1.json"})
    EXPECT_FALSE(fs::exists(build_ / "cases/medium_onesize" / stale)) << stale;
}

// A case's placement and strap settings reach straps and assemble alike (the straps laid for the
// gap and thickness the model gets), are tracked (a change re-runs those two stages and nothing
// before them; a failed re-run leaves no model of the old settings), and are never taken from the
// shell's environment.
TEST_F(CasesMake, case_settings_reach_straps_and_assemble_and_a_change_reruns_only_them) {
  std::vector<std::string> ran;
  ASSERT_EQ(make("case=medium_onesize", &ran), 0) << log_text(ran);
  const fs::path c = build_ / "cases/medium_onesize";
  const std::string settings = "STRAP_LENGTH_MM=280 GAP_MM=2.5 STRAP_THICKNESS_MM=1.5 BRIDGE_OFFSET_MM=-2";
  ASSERT_EQ(make("case=medium_onesize " + settings, &ran), 0) << log_text(ran);
  EXPECT_EQ(ran.size(), 2u) << log_text(ran);
  EXPECT_EQ(count(ran, "straps", "/cases/medium_onesize/"), 1) << log_text(ran);
  EXPECT_EQ(count(ran, "assemble", "/cases/medium_onesize/"), 1) << log_text(ran);
  const std::string straps = file_text(c / "straps.msh"), model = file_text(c / "model.msh");
  for (const char* o : {"--length-mm 280", "--gap-mm 2.5", "--thickness-mm 1.5", "--bridge-offset-mm -2"})
    EXPECT_NE(straps.find(o), std::string::npos) << o << ": " << straps;
  for (const char* o : {"--gap-mm 2.5", "--strap-thickness-mm 1.5", "--bridge-offset-mm -2"})
    EXPECT_NE(model.find(o), std::string::npos) << o << ": " << model;
  EXPECT_EQ(model.find("--length-mm"), std::string::npos) << model;
  EXPECT_NE(file_text(build_ / "make.out").find("settings STRAP_LENGTH_MM=280 STRAP_THICKNESS_MM=1.5 GAP_MM=2.5 BRIDGE_OFFSET_MM=-2"),
            std::string::npos) << log_text(ran);
  ASSERT_EQ(make("case=medium_onesize " + settings, &ran), 0);
  EXPECT_TRUE(ran.empty()) << log_text(ran);
  // a dry run with another setting lists those two stages, runs nothing and changes nothing
  const std::string before = folder_state(build_);
  ASSERT_EQ(make("-n case=medium_onesize STRAP_LENGTH_MM=250", &ran), 0);
  EXPECT_TRUE(ran.empty()) << log_text(ran);
  EXPECT_EQ(folder_state(build_), before);
  const std::string dry = file_text(build_ / "make.out");
  EXPECT_NE(dry.find("/straps --head"), std::string::npos) << dry;
  EXPECT_NE(dry.find("--length-mm 250"), std::string::npos) << dry;
  EXPECT_NE(dry.find("/assemble --head"), std::string::npos) << dry;
  EXPECT_EQ(dry.find("/layers --in"), std::string::npos) << dry;
  // from the environment: ignored (nothing re-runs, the settings stay those of the command line)
  ASSERT_EQ(make("case=medium_onesize " + settings, &ran, "GAP_MM=7 MAX_RIM_OFF_MM=30"), 0);
  EXPECT_TRUE(ran.empty()) << log_text(ran);
  // back to the defaults: the two stages again, without options
  ASSERT_EQ(make("case=medium_onesize", &ran), 0);
  EXPECT_EQ(ran.size(), 2u) << log_text(ran);
  EXPECT_EQ(file_text(c / "straps.msh").find("--length-mm"), std::string::npos);
  EXPECT_EQ(file_text(c / "model.msh").find("--gap-mm"), std::string::npos);
  ASSERT_EQ(make("case=medium_onesize", &ran, "GAP_MM=7"), 0);
  EXPECT_TRUE(ran.empty()) << log_text(ran);
  // a changed setting whose straps fail: no model of the old settings is left
  EXPECT_NE(make("case=medium_onesize STRAP_LENGTH_MM=250", &ran, "FAIL_STAGE=straps"), 0);
  for (const char* stale : {"straps.msh", "model.msh", "stage1.json", "stage2.json"})
    EXPECT_FALSE(fs::exists(c / stale)) << stale;
}

// The build folder reached through a link (a cluster's /home, a login node's path): the whole
// shared chain re-ran, since inputs.txt named the scans by the path given, and again on the way
// back (sweep P). Paths in the build folder are recorded from it.
TEST_F(CasesMake, a_build_folder_reached_through_a_link_reruns_nothing) {
  std::vector<std::string> ran;
  ASSERT_EQ(make("case=medium_onesize", &ran), 0) << log_text(ran);
  ASSERT_GT(ran.size(), 10u);
  const fs::path link = build_.string() + "_link";
  fs::remove(link);
  fs::create_directory_symlink(build_, link);
  for (const fs::path& build : {link, build_}) {
    fs::remove(build_ / "log.txt");
    ASSERT_EQ(run_command("make --no-print-directory -C " SOURCE_DIR " -f Makefile.cases case=medium_onesize BUILD=" +
                          build.string() + " > " + (build_ / "make.out").string() + " 2>&1"),
              0)
        << file_text(build_ / "make.out");
    EXPECT_FALSE(fs::exists(build_ / "log.txt")) << build << ": " << file_text(build_ / "log.txt");
  }
  fs::remove(link);
}

// What sweep P found make doing on a shared workstation. Two makes of one case at once (with and
// without a user's scan, or with two settings) both said done over outputs of the other's making:
// a second make now waits for the first. A case folder where inputs.txt cannot be written (full,
// read-only) printed the shell's error and said done with a setting never recorded: now make
// stops before any stage. A BUILD with a space in it had make rm -rf the folder before the space.
TEST_F(CasesMake, one_make_at_a_time_a_failed_set_up_stops_and_build_has_no_space) {
  std::vector<std::string> ran;
  ASSERT_EQ(make("case=medium_onesize", &ran), 0) << log_text(ran);
  const fs::path c = build_ / "cases/medium_onesize";
  const std::string first = (build_ / "first.out").string();
  ASSERT_EQ(run_command("(SLEEP_STAGE=straps make --no-print-directory -C " SOURCE_DIR " -f Makefile.cases BUILD=" +
                        build_.string() + " case=medium_onesize STRAP_LENGTH_MM=280 > " + first + " 2>&1; echo $? > " +
                        first + ".rc) > /dev/null 2>&1 &"),
            0);
  ASSERT_FALSE(fs::exists(first + ".rc"));  // running in the background
  for (int k = 0; k < 600 && !fs::exists(build_ / "sleeping"); ++k) run_command("sleep 0.05");
  ASSERT_TRUE(fs::exists(build_ / "sleeping")) << file_text(first);
  ASSERT_EQ(make("case=medium_onesize", &ran), 0) << log_text(ran);
  EXPECT_NE(file_text(build_ / "make.out").find("case medium_onesize: waiting for the make running cases in "),
            std::string::npos)
      << file_text(build_ / "make.out");
  ASSERT_TRUE(fs::exists(first + ".rc"));  // the second ran after the first had ended
  EXPECT_EQ(file_text(first + ".rc"), "0\n") << file_text(first);
  EXPECT_EQ(count(ran, "straps", "/cases/medium_onesize/"), 1) << log_text(ran);  // its own settings again
  EXPECT_EQ(file_text(c / "straps.msh").find("--length-mm"), std::string::npos);
  // inputs.txt cannot be written (as on a full disk): nothing runs, one line says where
  fs::create_directories(c / "inputs.txt.new");
  const std::string model_before = file_text(c / "model.msh");
  EXPECT_NE(make("case=medium_onesize GAP_MM=2.5", &ran), 0);
  EXPECT_TRUE(ran.empty()) << log_text(ran);
  EXPECT_NE(file_text(build_ / "make.out").find("case medium_onesize: cannot set up " + (c / "inputs.txt").string()),
            std::string::npos)
      << file_text(build_ / "make.out");
  EXPECT_EQ(file_text(c / "model.msh"), model_before);
  fs::remove_all(c / "inputs.txt.new");
  ASSERT_EQ(make("case=medium_onesize GAP_MM=2.5", &ran), 0);
  EXPECT_EQ(ran.size(), 2u) << log_text(ran);
  // BUILD with a space, and the source folder as BUILD: refused, nothing removed
  fs::create_directories(build_ / "victim");
  std::ofstream(build_ / "victim/keep.txt") << "keep\n";
  for (const std::string& bad : {"'BUILD=" + (build_ / "victim").string() + " x'", std::string("BUILD=.")}) {
    EXPECT_NE(run_command("make --no-print-directory -C " SOURCE_DIR " -f Makefile.cases case=medium_onesize " + bad +
                          " > " + (build_ / "make.out").string() + " 2>&1"),
              0)
        << bad;
    EXPECT_NE(file_text(build_ / "make.out").find(bad == "BUILD=." ? "is this source folder or holds it" : "make cannot take a folder with a space"),
              std::string::npos)
        << file_text(build_ / "make.out");
    EXPECT_TRUE(fs::exists(build_ / "victim/keep.txt")) << bad;
    EXPECT_TRUE(fs::exists(fs::path(SOURCE_DIR) / "Makefile.cases"));
  }
}

}  // namespace
