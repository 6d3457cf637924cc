/// surface_mesh: conforming part-wise triangle mesh of a fitted head (or respirator inner face)
/// for `layers`.
///
/// Inputs:  --in fitted.ply (from `fit`; a `segment` output works too: face property "part")
/// Outputs: --out surface.msh (gmsh MSH 4.1 ASCII, 3-node triangles, one physical group per part:
///          back_of_head, forehead, left_cheek, right_cheek, chin; or respirator_inner)
/// Sample runs:
///   surface_mesh --in head/fitted.ply --out head/surface.msh
///   surface_mesh --in respirator/fitted.ply --kind respirator --size 3 --out respirator/surface.msh

#include <cstdio>

#include "meshing/surface_mesh.h"
#include "pipeline/atomic_write.h"
#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/gmsh_session.h"
#include "pipeline/progress.h"
#include "pipeline/read_scan.h"
#include "pipeline/require_affordable_edge.h"
#include "pipeline/units.h"
#include "pipeline/write_gmsh_model.h"

int main(int argc, char** argv) {
  std::string in, out, kind = "head";
  double size_mm = meshing::default_size_mm, back_mm = meshing::default_back_size_mm, min_gamma = 0.3;
  pipeline::Cli cli("surface_mesh", "Meshes a fitted, part-labelled surface into a conforming triangle mesh.");
  cli.option("-i", "--in", &in, "fitted mesh (.ply with face property 'part')", pipeline::required);
  cli.option("-o", "--out", &out, "surface mesh (.msh 4.1)", pipeline::required);
  cli.option("-k", "--kind", &kind, "head | respirator");
  cli.option("-s", "--size", &size_mm, "edge length on the face parts / respirator [mm] (6.4 gives the generated medium head ~13,000 wedges in layers, the paper's model 13,570)", 0.5, 50.0);
  cli.option("-b", "--back-size", &back_mm, "edge length on back_of_head [mm] (a rigid shell, no wedges); without it min(7, 2 x --size), at most 2.5 x --size (coarser leaves no good triangle at the cut)", 0.5, 50.0);
  cli.option("-g", "--min-gamma", &min_gamma, "fail below this triangle quality", 0.0, 1.0);
  return pipeline::run_main(cli, argc, argv, [&] {
    pipeline::require_distinct_files({{"--in", in}, {"--out", out}});
    if (kind != "head" && kind != "respirator")
      throw pipeline::Error(pipeline::ErrorKind::usage, "--kind: got '" + kind + "', expected head or respirator");
    pipeline::require_extension("--out", out, {".msh"});
    pipeline::require_writable_outputs({out});
    if (!cli.given("--back-size")) back_mm = meshing::default_back_size_for(size_mm);
    if (kind == "head" && back_mm > meshing::max_back_size_ratio * size_mm)
      throw pipeline::Error(pipeline::ErrorKind::usage,
                            "--back-size " + pipeline::format_number(back_mm) + " mm is more than " +
                                pipeline::format_number(meshing::max_back_size_ratio) + " times --size " +
                                pipeline::format_number(size_mm) + " mm: the cut between them gets no good triangle at "
                                "any size; give at most " + pipeline::format_number(meshing::max_back_size_ratio * size_mm) +
                                " mm, or leave --back-size out (" + pipeline::format_number(meshing::default_back_size_for(size_mm)) +
                                " mm)");
    pipeline::Progress progress("surface_mesh", 0);
    const pipeline::SurfaceMesh fitted = pipeline::read_surface_mesh(in);
    pipeline::require_mm(in, pipeline::largest_extent(fitted.points()), kind);
    // the whole surface's area for both: a bound on each
    pipeline::require_affordable_edge("--size", size_mm, fitted, meshing::max_surface_mesh_triangles);
    pipeline::require_affordable_edge("--back-size", back_mm, fitted, meshing::max_surface_mesh_triangles);
    pipeline::GmshSession session;
    std::size_t total = 0;
    meshing::SurfaceMeshRetries retries;
    const auto parts = pipeline::naming_file(
        in, [&] {
          return meshing::surface_mesh(fitted, kind, size_mm, back_mm, min_gamma, meshing::default_max_retries, &retries,
                                       &progress);
        });
    if (!retries.failed.empty())
      pipeline::log("surface_mesh", "meshed at size " + pipeline::format_number(retries.size_mm) + " mm" +
                                        (kind == "head" ? ", back " + pipeline::format_number(retries.back_size_mm) + " mm"
                                                        : std::string()) +
                                        " instead of " + pipeline::format_number(size_mm) + " mm");
    for (const auto& p : parts) {
      char line[160];
      std::snprintf(line, sizeof line, "%-16s %6zu triangles  gamma min %.3f mean %.3f", p.name.c_str(), p.triangles,
                    p.min_gamma, p.mean_gamma);
      pipeline::log("surface_mesh", line);
      total += p.triangles;
    }
    pipeline::write_gmsh_model(out);
    progress.finish("wrote " + out + " (" + std::to_string(total) + " triangles)");
    return 0;
  });
}
