// The stage programs' output names, checked with the other usage checks before any input is
// read: exit 1, one line naming the option and the file, nothing written. Seconds (process
// launches only), so it runs with the fast tests.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>

#include "../last_line.h"
#include "../run_command.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;

// Every JSON output of the stages is named .json: `landmarks --out x.ply` wrote JSON into a file
// that the next stage (and a viewer) takes for a mesh. The name is checked with the other usage
// checks, before any input is read (the inputs here do not exist): exit 1, one line, no file.
TEST(stage_outputs, a_json_output_not_named_json_is_a_usage_error_before_any_work) {
  const fs::path dir = scratch_dir() / "json_outputs";
  fs::create_directories(dir);
  const std::string d = dir.string() + "/", none = d + "absent";
  const std::pair<std::string, std::string> runs[] = {
      {"landmarks --in " + none + ".ply --out " + d + "l.ply", "--out: '" + d + "l.ply'"},
      {"align --in " + none + ".ply --out " + d + "a.ply --transform " + d + "t.txt", "--transform: '" + d + "t.txt'"},
      {"repair --in " + none + ".ply --out " + d + "r.ply --report " + d + "r.ply.txt", "--report: '" + d + "r.ply.txt'"},
      {"layers --in " + none + ".msh --materials " + none + ".json --out " + d + "m.msh --report " + d + "rep",
       "--report: '" + d + "rep'"},
      {"assemble --head " + none + "1.msh --respirator " + none + "2.msh --straps " + none + "3.msh --landmarks " + none +
           ".json --materials " + none + "m.json --out " + d + "model.msh --deck1 " + d + "s1 --deck2 " + d + "s2.json",
       "--deck1: '" + d + "s1'"},
      {"assemble --head " + none + "1.msh --respirator " + none + "2.msh --straps " + none + "3.msh --landmarks " + none +
           ".json --materials " + none + "m.json --out " + d + "model.msh --deck1 " + d + "s1.json --deck2 " + d + "s2.msh",
       "--deck2: '" + d + "s2.msh'"}};
  for (const auto& [args, named] : runs) {
    const std::string log = d + "err.txt";
    EXPECT_EQ(run_command(std::string(BIN_DIR) + "/" + args + " 2> " + log), 1) << args;
    const std::string program = args.substr(0, args.find(' '));
    EXPECT_EQ(last_line_of(log), program + ": " + named + " must end in .json (see '" + program + " --help')");
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir)) files += e.path().filename() != "err.txt";
    EXPECT_EQ(files, 0u) << args;
  }
}

// assemble's --state1 names the stage I state the stage II deck starts from, which solve writes
// as state.bin: '' or a deck's name went into deck2 with exit 0 (solve then refused the deck).
TEST(stage_outputs, assemble_state1_not_named_bin_is_a_usage_error_before_any_work) {
  const fs::path dir = scratch_dir() / "state1";
  fs::create_directories(dir);
  const std::string d = dir.string() + "/", none = d + "absent";
  for (const std::string& state1 : {std::string("''"), d + "s1.json"}) {
    const std::string log = d + "err.txt";
    EXPECT_EQ(run_command(std::string(BIN_DIR) + "/assemble --head " + none + "1.msh --respirator " + none +
                          "2.msh --straps " + none + "3.msh --landmarks " + none + ".json --materials " + none +
                          "m.json --out " + d + "model.msh --deck1 " + d + "s1.json --deck2 " + d + "s2.json -S " +
                          state1 + " 2> " + log),
              1)
        << state1;
    EXPECT_NE(last_line_of(log).find("--state1: '"), std::string::npos) << last_line_of(log);
    EXPECT_NE(last_line_of(log).find(state1 == "''" ? "'' is empty: give a value, or leave --state1 out" : "' must end in .bin"),
              std::string::npos)
        << last_line_of(log);
  }
}
