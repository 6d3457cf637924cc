/// fit: fits a parametrized (CAD-like) surface to each part of a segmented head or respirator
/// inner face with gmsh, and measures the deviation of the fitted geometry from the input mesh.
///
/// Inputs:  --in segmented.ply (triangle mesh with int face property "part", from `segment`)
/// Outputs: --out fitted.msh (gmsh MSH 4.1: discrete surfaces with their parametrizations and
///          boundary curves, one named physical group per part)
/// Sample runs:
///   fit --in head/segmented.ply --out head/fitted.msh
///   fit --in respirator/segmented.ply --kind respirator --out respirator/fitted.msh
#include <gmsh.h>

#include <cstdio>

#include "pipeline/atomic_write.h"
#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/progress.h"
#include "pipeline/read_scan.h"
#include "scan2cad/fit.h"

int main(int argc, char** argv) {
  std::string in, out, kind = "head";
  double check_mm = 2.0;
  pipeline::Cli cli("fit", "Fits a parametrized gmsh surface to each part of a segmented surface.");
  cli.option("-i", "--in", &in, "segmented mesh (.ply with face property 'part')", pipeline::required);
  cli.option("-o", "--out", &out, "fitted geometry (.msh)", pipeline::required);
  cli.option("-k", "--kind", &kind, "head | respirator (default head)");
  cli.option("-c", "--check-size", &check_mm, "mesh size of the deviation check [mm] (default 2)", 0.2, 20.0);
  return pipeline::run_main(cli, argc, argv, [&] {
    // 1. Options and input
    if (kind != "head" && kind != "respirator")
      throw pipeline::Error(pipeline::ErrorKind::usage, "--kind: got '" + kind + "', expected head or respirator");
    pipeline::Progress progress("fit", 0);
    const pipeline::SurfaceMesh mesh = pipeline::read_surface_mesh(in);
    struct Session {
      Session() { gmsh::initialize(); gmsh::option::setNumber("General.Terminal", 1);
                  gmsh::option::setNumber("General.NumThreads", 1); }
      ~Session() {
        try { gmsh::finalize(); } catch (...) {}  // an error already being reported
      }
    } session;
    // 2. Fit, 3. write the geometry, 4. measure the deviation
    progress.step("parametrizing the parts");
    const auto parts = scan2cad::fit_surfaces(mesh, kind);
    pipeline::write_atomic(out, [](const std::string& tmp) {
      gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
      gmsh::option::setNumber("Mesh.Binary", 0);
      gmsh::write(tmp);
    });
    progress.step("measuring the deviation (check mesh " + std::to_string(check_mm) + " mm)");
    for (const auto& d : scan2cad::fit_deviation(mesh, parts, check_mm)) {
      char line[200];
      std::snprintf(line, sizeof line, "%-16s deviation rms %.4f max %.4f mm (%zu points); chord rms %.3f max %.3f mm",
                    d.name.c_str(), d.rms_mm, d.max_mm, d.samples, d.chord_rms_mm, d.chord_max_mm);
      pipeline::log("fit", line);
    }
    progress.finish("wrote " + out);
    return 0;
  });
}
