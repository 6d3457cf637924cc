#pragma once
/// gmsh must be initialised once per process; both the reader and the writer call this.
/// gmsh also sets the OpenMP thread count (General.NumThreads, default 1) when it initialises
/// and reads files: KeepOmpThreads restores the caller's count when it goes out of scope.
#include <omp.h>

#include <gmsh.h>

namespace solve::internal {

struct KeepOmpThreads {
  int n = omp_get_max_threads();
  ~KeepOmpThreads() { omp_set_num_threads(n); }
};

inline void ensure_gmsh() {
  static const bool ready = [] {
    gmsh::initialize();
    gmsh::option::setNumber("General.Terminal", 0);
    return true;
  }();
  (void)ready;
}

}  // namespace solve::internal
