#include "pipeline/progress.h"

#include <cstdio>

namespace pipeline {

using clock = std::chrono::steady_clock;

Progress::Progress(std::string stage, std::size_t total, double min_interval_s)
    : stage_(std::move(stage)), total_(total), min_interval_s_(min_interval_s),
      start_(clock::now()), last_(start_ - std::chrono::hours(1)) {}

double Progress::elapsed_s() const {
  return std::chrono::duration<double>(clock::now() - start_).count();
}

void Progress::update(std::size_t done, const std::string& step) {
  const auto now = clock::now();
  // the last unit of a known total is always printed; without a total (0) every line is limited
  if (std::chrono::duration<double>(now - last_).count() < min_interval_s_ && (total_ == 0 || done < total_)) return;
  last_ = now;
  const double t = elapsed_s();
  if (total_ > 0 && done > 0) {
    const double eta = t * double(total_ - std::min(done, total_)) / double(done);
    std::fprintf(stderr, "%s: %s %zu/%zu (%.0f%%) elapsed %.1f s ETA %.1f s\n", stage_.c_str(),
                 step.c_str(), done, total_, 100.0 * double(done) / double(total_), t, eta);
  } else {
    std::fprintf(stderr, "%s: %s %zu elapsed %.1f s\n", stage_.c_str(), step.c_str(), done, t);
  }
}

void Progress::step(const std::string& step) {
  std::fprintf(stderr, "%s: %s (%.1f s)\n", stage_.c_str(), step.c_str(), elapsed_s());
}

void Progress::finish(const std::string& summary) {
  std::fprintf(stderr, "%s: done in %.1f s%s%s\n", stage_.c_str(), elapsed_s(),
               summary.empty() ? "" : ": ", summary.c_str());
}

void log(const std::string& stage, const std::string& message) {
  std::fprintf(stderr, "%s: %s\n", stage.c_str(), message.c_str());
}

}  // namespace pipeline
