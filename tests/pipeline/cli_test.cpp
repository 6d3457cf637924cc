#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "../bad_input_message.h"

namespace {

struct Args {
  std::vector<std::string> s;
  std::vector<char*> v;
  explicit Args(std::vector<std::string> a) : s(std::move(a)) {
    for (auto& x : s) v.push_back(x.data());
  }
  int argc() { return int(v.size()); }
  char** argv() { return v.data(); }
};

}  // namespace

TEST(cli, parses_long_short_and_inline_values) {
  std::string in;
  double edge = 2.0;
  int n = 3;
  bool verbose = false;
  pipeline::Cli cli("prog", "test");
  cli.option("-i", "--in", &in, "input", pipeline::required)
      .option("-e", "--edge", &edge, "edge [mm]", 0.1, 10)
      .option("-n", "--count", &n, "count", 1, 9)
      .flag("-v", "--verbose", &verbose, "talk");
  Args a({"prog", "-i", "x.ply", "--edge=1.5", "-n", "7", "--verbose"});
  ASSERT_TRUE(cli.parse(a.argc(), a.argv()));
  EXPECT_EQ(in, "x.ply");
  EXPECT_DOUBLE_EQ(edge, 1.5);
  EXPECT_EQ(n, 7);
  EXPECT_TRUE(verbose);
  // which options were given, for defaults that follow another option (surface_mesh --back-size)
  EXPECT_TRUE(cli.given("--edge"));
  Args b({"prog", "-i", "x.ply"});
  ASSERT_TRUE(cli.parse(b.argc(), b.argv()));
  EXPECT_FALSE(cli.given("--edge"));
  EXPECT_TRUE(cli.given("--in"));
  EXPECT_THROW(cli.given("--size"), pipeline::Error);
  // --help gives each number's range with its default (the ranges were enforced but not shown)
  const std::string help = cli.usage();
  EXPECT_NE(help.find("edge [mm] [default: 1.5; 0.1 to 10]"), std::string::npos) << help;
  EXPECT_NE(help.find("count [default: 7; 1 to 9]"), std::string::npos) << help;
}

TEST(cli, rejects_absurd_and_malformed_values) {
  std::string in;
  double edge = 2.0;
  bool verbose = false;
  pipeline::Cli cli("prog", "test");
  cli.option("-i", "--in", &in, "input", pipeline::required)
      .option("-e", "--edge", &edge, "edge", 0.1, 10)
      .flag("-v", "--verbose", &verbose, "talk");
  for (auto bad : std::vector<std::vector<std::string>>{{"prog", "-i", "a", "-e", "nan"},
                                                         {"prog", "-i", "a", "-e", "100"},
                                                         {"prog", "-i", "a", "-e", "2mm"},
                                                         {"prog", "-i", "a", "-e", "0x8"},  // hexadecimal
                                                         {"prog", "-i", "a", "-e", "2", "--edge", "3"},  // twice
                                                         {"prog", "-i", "a", "--in", "a"},
                                                         {"prog", "-i", "a", "--verbose=false"},  // a flag's value
                                                         {"prog", "-e", "2"},
                                                         {"prog", "-i", "a", "--bogus"},
                                                         {"prog", "-i"}}) {
    Args a(bad);
    try {
      cli.parse(a.argc(), a.argv());
      ADD_FAILURE() << "accepted " << bad.back();
    } catch (const pipeline::Error& e) {
      EXPECT_EQ(e.kind, pipeline::ErrorKind::usage);
    }
  }
  auto message = [&](std::vector<std::string> args) {
    Args a(std::move(args));
    return error_message(pipeline::ErrorKind::usage, [&] { cli.parse(a.argc(), a.argv()); });
  };
  EXPECT_EQ(message({"prog", "-i", "a", "-e", "2", "--edge", "3"}), "--edge given twice: give each option once");
  EXPECT_EQ(message({"prog", "-i", "a", "--verbose=false"}), "--verbose is a flag and takes no value, got 'false'");
  EXPECT_EQ(message({"prog", "-i", "a", "-e", "0x8"}), "--edge: expected a finite number, got '0x8'");
  // an empty value (an unset shell variable): solve --restart "" ran from t = 0 as if not given
  EXPECT_EQ(message({"prog", "-i", ""}), "--in: '' is empty: give a value, or leave --in out");
  EXPECT_EQ(message({"prog", "--in="}), "--in: '' is empty: give a value, or leave --in out");
  // a range's ends are in it, as --help says ("0.1 to 10"); just past them is not (refusing the
  // top end passed every test, sweep N)
  for (const char* end : {"0.1", "10"}) {
    Args a({"prog", "-i", "a", "-e", end});
    EXPECT_NO_THROW(cli.parse(a.argc(), a.argv())) << end;
    EXPECT_EQ(edge, std::stod(end));
  }
  EXPECT_EQ(message({"prog", "-i", "a", "-e", "10.0001"}), "--edge: 10.0001 is out of range [0.1, 10]");
  EXPECT_EQ(message({"prog", "-i", "a", "-e", "0.0999"}), "--edge: 0.0999 is out of range [0.1, 10]");
}

// A seed is a whole number read exactly: through a double, 1.5 and 1.999 gave seed 1's bytes
// while the log said "seed=1.5", and seeds above 2^53 were logged alike (9.0072e+15).
TEST(cli, a_whole_number_option_is_read_exactly) {
  std::uint64_t seed = 1;
  pipeline::Cli cli("prog", "test");
  cli.option("-S", "--seed", &seed, "seed");
  Args a({"prog", "--seed", "9007199254740993"});
  ASSERT_TRUE(cli.parse(a.argc(), a.argv()));
  EXPECT_EQ(seed, 9007199254740993ull);
  EXPECT_NE(cli.usage().find("seed [default: 9007199254740993]"), std::string::npos) << cli.usage();
  Args b({"prog", "--seed", "18446744073709551615"});
  ASSERT_TRUE(cli.parse(b.argc(), b.argv()));
  EXPECT_EQ(seed, 18446744073709551615ull);
  for (const std::string bad : {"1.5", "-1", "1e3", "0x10", "", "18446744073709551616", " 7"}) {
    Args c({"prog", "--seed", bad});
    EXPECT_EQ(error_message(pipeline::ErrorKind::usage, [&] { cli.parse(c.argc(), c.argv()); }),
              "--seed: expected a whole number from 0 to 18446744073709551615, got '" + bad + "'");
  }
}

TEST(cli, run_main_maps_error_kinds_to_exit_codes) {
  pipeline::Cli cli("prog", "test");
  Args a({"prog"});
  EXPECT_EQ(pipeline::run_main(cli, a.argc(), a.argv(), [] { return 0; }), 0);
  EXPECT_EQ(pipeline::run_main(cli, a.argc(), a.argv(), []() -> int { throw pipeline::bad_input("f", "x"); }), 2);
  EXPECT_EQ(pipeline::run_main(cli, a.argc(), a.argv(), []() -> int { throw pipeline::algorithm_failed("f", "x"); }), 3);
  EXPECT_EQ(pipeline::run_main(cli, a.argc(), a.argv(), []() -> int { throw pipeline::io_failed("f", "x"); }), 4);
  EXPECT_EQ(pipeline::run_main(cli, a.argc(), a.argv(), []() -> int { throw std::string("gmsh failed"); }), 3);
  Args help({"prog", "--help"});
  EXPECT_EQ(pipeline::run_main(cli, help.argc(), help.argv(), [] { return 7; }), 0);
}

// Every failure is one stderr line; a usage error's ends with the pointer to --help (it was a
// second line, and the parser's own messages said "(see --help)" on top of it).
TEST(cli, run_main_prints_one_line_per_usage_error) {
  std::string in;
  pipeline::Cli cli("prog", "test");
  cli.option("-i", "--in", &in, "input", pipeline::required);
  const auto stderr_of = [&](std::vector<std::string> args, int expected_exit) {
    Args a(std::move(args));
    testing::internal::CaptureStderr();
    EXPECT_EQ(pipeline::run_main(cli, a.argc(), a.argv(), [] { return 0; }), expected_exit);
    return testing::internal::GetCapturedStderr();
  };
  EXPECT_EQ(stderr_of({"prog", "-i", "a", "--bogus"}, 1), "prog: unknown option '--bogus' (see 'prog --help')\n");
  EXPECT_EQ(stderr_of({"prog"}, 1), "prog: missing required option --in (see 'prog --help')\n");
  // an error of another kind has no pointer (the options line comes first: the parse succeeded)
  Args a({"prog", "-i", "a"});
  testing::internal::CaptureStderr();
  EXPECT_EQ(pipeline::run_main(cli, a.argc(), a.argv(), []() -> int { throw pipeline::bad_input("a", "empty"); }), 2);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "prog: options: in=a\nprog: a: empty\n");
  // a library's message over several lines (CGAL's assertions take four) is joined into one
  testing::internal::CaptureStderr();
  EXPECT_EQ(pipeline::run_main(cli, a.argc(), a.argv(),
                               []() -> int { throw std::runtime_error("CGAL ERROR: assertion violation!\nFile: x.h\n"); }),
            3);
  EXPECT_EQ(testing::internal::GetCapturedStderr(),
            "prog: options: in=a\nprog: internal error: CGAL ERROR: assertion violation! / File: x.h\n");
}

// An output path's ending is checked before any work: the gmsh writers of surface_mesh, layers,
// straps and assemble failed after it with "Unknown output file format", naming no file.
TEST(require_extension, accepts_the_listed_endings_in_any_case_and_names_the_rest) {
  EXPECT_NO_THROW(pipeline::require_extension("--out", "a/b.ply", {".ply", ".msh"}));
  EXPECT_NO_THROW(pipeline::require_extension("--out", "B.MSH", {".ply", ".msh"}));
  const auto message = [](const std::string& path, const std::vector<std::string>& exts) {
    return error_message(pipeline::ErrorKind::usage, [&] { pipeline::require_extension("--out", path, exts); });
  };
  EXPECT_EQ(message("x.txt", {".msh"}), "--out: 'x.txt' must end in .msh");
  EXPECT_EQ(message("dir/", {".ply", ".xyz"}), "--out: 'dir/' must end in .ply or .xyz");
  EXPECT_EQ(message("x.ply.tmp", {".ply", ".off", ".obj", ".stl"}),
            "--out: 'x.ply.tmp' must end in .ply, .off, .obj or .stl");
}

TEST(require_distinct_files, the_same_file_under_two_options_is_a_usage_error) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("require_distinct_files_" + std::to_string(::getpid()));
  fs::create_directories(dir / "sub");
  const std::string a = (dir / "a.ply").string(), b = (dir / "b.ply").string(), link = (dir / "link.ply").string();
  std::ofstream(a) << "ply";
  fs::create_symlink(a, link);
  const auto message = [](const std::vector<std::pair<std::string, std::string>>& files) {
    return error_message(pipeline::ErrorKind::usage, [&] { pipeline::require_distinct_files(files); });
  };
  EXPECT_EQ(message({{"--in", a}, {"--out", b}, {"--report", ""}, {"--user", ""}}), "no error");
  EXPECT_EQ(message({{"--in", a}, {"--out", a}}),
            "--out '" + a + "' is the same file as --in: each file option needs a file of its own (an output must not replace an input)");
  EXPECT_EQ(message({{"--in", a}, {"--out", b}, {"--report", b}}).rfind("--report '" + b + "' is the same file as --out", 0), 0u);
  EXPECT_EQ(message({{"--in", link}, {"--out", a}}).rfind("--out '" + a + "' is the same file as --in", 0), 0u);
  // spelled differently, and not written yet
  const std::string other_spelling = (dir / "sub" / ".." / "b.ply").string();
  EXPECT_EQ(message({{"--out", b}, {"--report", other_spelling}}).rfind("--report '" + other_spelling + "' is the same file as --out", 0), 0u);
  fs::remove_all(dir);
}
