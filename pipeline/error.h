#pragma once
/// Errors of the pipeline. Library code throws pipeline::Error; only a stage's main()
/// maps the kind to an exit code (see run_main in cli.h).
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>

namespace pipeline {

/// What went wrong, and so which exit code the program returns.
enum class ErrorKind {
  usage = 1,      ///< bad command line
  bad_input = 2,  ///< the user's data is unusable (missing, empty, truncated, NaN, ...)
  algorithm = 3,  ///< the data was read but the algorithm could not finish
  io = 4,         ///< writing an output failed
  interrupted = 130  ///< stopped by SIGINT (Ctrl-C) or SIGTERM (the shell's 128 + SIGINT)
};

/// An error with a kind. The message names the file or entity first:
/// "p03/surface.ply: face 1841 degenerate: area 0 mm², expected > 1e-6".
struct Error : std::runtime_error {
  ErrorKind kind;
  Error(ErrorKind k, const std::string& message) : std::runtime_error(message), kind(k) {}
};

/// A number as a message shows it: 0.1206, 1e+300, 250 (std::to_string gives 0.120600).
inline std::string format_number(double v) {
  std::ostringstream ss;
  ss << v;
  return ss.str();
}

/// A position as a message shows it, to 0.1 mm: "(12.3, -4.5, 67.8) mm". Messages name places by
/// position, which any viewer shows, not by an index a program counted (a file's tags may differ).
inline std::string format_position_mm(double x, double y, double z) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.1f, %.1f, %.1f) mm", x, y, z);
  return text;
}

inline Error bad_input(const std::string& what, const std::string& problem) {
  return Error(ErrorKind::bad_input, what + ": " + problem);
}
inline Error algorithm_failed(const std::string& what, const std::string& problem) {
  return Error(ErrorKind::algorithm, what + ": " + problem);
}
inline Error io_failed(const std::string& what, const std::string& problem) {
  return Error(ErrorKind::io, what + ": " + problem);
}

/// Runs f() and returns what it returns; a pipeline::Error it throws is re-thrown with "path: "
/// in front. Library functions name what they were given ("respirator: ..."); a stage wraps
/// its calls on a file's contents in this so the user's error line also names the file.
template <class F>
auto naming_file(const std::string& path, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error& e) {
    throw Error(e.kind, path + ": " + e.what());
  }
}

}  // namespace pipeline
