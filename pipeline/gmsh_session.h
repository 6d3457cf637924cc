#pragma once
/// gmsh_session: the gmsh API initialised for one task (a read, a write, a meshing) and
/// finalised after it.
///
/// gmsh keeps global state, so each reader and writer of .msh files, and each stage that meshes
/// with gmsh, opens a session for the duration of its work (sessions do not nest). gmsh also sets
/// the OpenMP thread count (General.NumThreads) when it initialises and reads files; the session
/// gives the caller's count back when it closes, so a solver running on two threads keeps them
/// after writing a mesh.
#include <omp.h>

#include <gmsh.h>

namespace pipeline {

struct GmshSession {
  GmshSession() {
    gmsh::initialize();
    gmsh::option::setNumber("General.Terminal", 0);  // errors come back as exceptions, not prints
    gmsh::option::setNumber("General.Verbosity", 1);
  }
  ~GmshSession() {
    try {
      gmsh::finalize();
    } catch (...) {  // closing while an error is being reported: that error is the one to show
    }
    omp_set_num_threads(omp_threads);
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

 private:
  int omp_threads = omp_get_max_threads();
};

}  // namespace pipeline
