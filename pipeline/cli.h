#pragma once
/// Command-line options and the error-to-exit-code mapping shared by every stage program.
///
/// Usage (in a stage's main):
///   std::string in, out; double edge_mm = 2.0;
///   pipeline::Cli cli("repair", "Repairs a scanned surface ...");
///   cli.option("-i", "--in", &in, "input mesh (PLY/STL/OBJ/OFF)", pipeline::required);
///   cli.option("-e", "--edge", &edge_mm, "target edge length [mm]", 0.05, 50.0);
///   return pipeline::run_main(cli, argc, argv, [&] { ...; return 0; });
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace pipeline {

inline constexpr bool required = true;

class Cli {
 public:
  Cli(std::string program, std::string description);

  /// A string option; `is_required` makes it mandatory.
  Cli& option(const std::string& short_flag, const std::string& long_flag, std::string* value,
              const std::string& help, bool is_required = false);
  /// A number option with an inclusive valid range; NaN and out-of-range values are usage errors.
  Cli& option(const std::string& short_flag, const std::string& long_flag, double* value,
              const std::string& help, double min = -std::numeric_limits<double>::max(),
              double max = std::numeric_limits<double>::max());
  Cli& option(const std::string& short_flag, const std::string& long_flag, int* value,
              const std::string& help, int min = std::numeric_limits<int>::min(),
              int max = std::numeric_limits<int>::max());
  /// A whole-number option of the full 64-bit range (a random seed): digits only, read exactly
  /// (1.5, -1, 1e3 and values above 2^64 - 1 are usage errors; it was read through a double,
  /// 2^53 + 1 as 2^53 and 1.5 as 1).
  Cli& option(const std::string& short_flag, const std::string& long_flag, std::uint64_t* value,
              const std::string& help);
  /// A boolean switch (no argument).
  Cli& flag(const std::string& short_flag, const std::string& long_flag, bool* value,
            const std::string& help);

  /// Parses argv. Returns false when --help was printed (the program should exit 0).
  /// @throws Error(usage) on an unknown flag, a missing or malformed value, or a missing
  ///         required option.
  bool parse(int argc, char** argv);
  std::string usage() const;
  /// "name=value" of every option, for the log line after parsing.
  std::string resolved() const;
  const std::string& program() const { return program_; }
  /// Whether the last parse was given `long_flag` ("--back-size"), for a default that depends on
  /// another option. @throws Error(usage) for a flag the program does not have.
  bool given(const std::string& long_flag) const;

 private:
  struct Opt {
    Opt(std::string s, std::string l, std::string h)
        : short_flag(std::move(s)), long_flag(std::move(l)), help(std::move(h)) {}
    std::string short_flag, long_flag, help;
    std::string range;  // "0.5 to 50" for a number with bounds, shown by usage()
    bool is_flag = false, is_required = false, seen = false;
    std::function<void(const std::string&)> set;
    std::function<std::string()> get;
  };
  Opt* find(const std::string& flag);
  std::string program_, description_;
  std::vector<Opt> opts_;
};

/// Checks, before any work, that an output path names a format the stage writes: a wrong
/// extension otherwise failed only after the work (exit 4), or inside gmsh ("Unknown output
/// file format", naming no file).
/// @param[in] option      the option's long flag, for the message ("--out")
/// @param[in] extensions  accepted endings, lower case with the dot (".ply")
/// @throws Error(usage) "--out: 'x.txt' must end in .ply, .off, .obj or .stl" otherwise.
void require_extension(const std::string& option, const std::string& path, const std::vector<std::string>& extensions);

/// Checks, before any work, that no two file options of a stage name the same file: `--out` equal
/// to `--in` replaced the scan with the stage's result, and `--report` equal to `--out`, or
/// `--deck1` equal to `--materials`, wrote one over the other, all with exit 0. Paths are compared
/// as files (`./a.ply`, `a.ply` and a link to it are one file); empty paths (options not given)
/// are skipped.
/// @param[in] files  (long flag, path) of every option that names a file the stage reads or writes
/// @throws Error(usage) "--out 'a.ply' is the same file as --in: each file option needs a file of
///         its own (an output must not replace an input)"
void require_distinct_files(const std::vector<std::pair<std::string, std::string>>& files);

/// Parses the command line, runs `body` and maps exceptions to exit codes:
/// usage 1, bad input 2, algorithm 3, I/O 4 (pipeline::Error kinds); other exceptions 3.
/// Each error is one line on stderr: "program: message", and for a usage error
/// "program: message (see 'program --help')".
int run_main(Cli& cli, int argc, char** argv, const std::function<int()>& body);

}  // namespace pipeline
