#pragma once
/// gmsh must be initialised once per process; both the reader and the writer call this.
#include <gmsh.h>

namespace solve::internal {
inline void ensure_gmsh() {
  static const bool ready = [] {
    gmsh::initialize();
    gmsh::option::setNumber("General.Terminal", 0);
    return true;
  }();
  (void)ready;
}
}  // namespace solve::internal
