#pragma once
/// Progress on stderr for long work: "stage: step 10/40 (25%) elapsed 3.0 s ETA 9.0 s" (without a
/// total: "stage: step 10 elapsed 3.0 s").
/// Lines are rate-limited (at most one every `min_interval_s`) so logs stay short.
#include <chrono>
#include <cstddef>
#include <string>

namespace pipeline {

class Progress {
 public:
  /// @param stage  the program or stage name printed first
  /// @param total  number of work units (0 if unknown: no ETA is printed)
  Progress(std::string stage, std::size_t total, double min_interval_s = 2.0);
  /// Reports that `done` units are finished, while doing `step`.
  void update(std::size_t done, const std::string& step = "");
  /// Re-estimates the total: work whose units change size as it goes (solve's steps, when the
  /// time step shrinks) printed past 100 % ("16168/15705 (103%) ETA 0.0 s", sweep M).
  void set_total(std::size_t total) { total_ = total; }
  /// Starts a new named step without a count (printed at once).
  void step(const std::string& step);
  /// Prints the final line with the elapsed time.
  void finish(const std::string& summary = "");
  /// Seconds since construction.
  double elapsed_s() const;

 private:
  std::string stage_;
  std::size_t total_;
  double min_interval_s_;
  std::chrono::steady_clock::time_point start_, last_;
};

/// Prints "stage: message" on stderr (the one logging function of the pipeline).
void log(const std::string& stage, const std::string& message);

}  // namespace pipeline
