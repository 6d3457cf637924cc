#pragma once
/// A seeded random source whose output is identical on every platform and standard library.
///
/// Why by hand: std::mt19937_64 is fully specified by the C++ standard (same seed → same
/// 64-bit sequence everywhere), but std::uniform_real_distribution and std::normal_distribution
/// are implementation-defined and differ between libstdc++, libc++ and MSVC. The generated
/// scans must be byte-identical for a given seed, so the distributions below are written out:
/// uniform from the top 53 bits, normal by the Box–Muller transform.
#include <cmath>
#include <cstdint>
#include <random>

namespace generator {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}

  /// Uniform in [0, 1).
  double uniform() { return double(engine_() >> 11) * (1.0 / 9007199254740992.0); }
  /// Uniform in [a, b).
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  /// Uniform integer in [0, n); n > 0. (Modulo bias < n / 2^64: negligible.)
  std::uint64_t index(std::uint64_t n) { return engine_() % n; }
  /// Standard normal N(0, 1) by Box–Muller (both values of a pair are used).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 6.283185307179586 * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace generator
