// align: puts a repaired head or respirator surface into the paper's frame (x lateral, +x = the
// subject's left; y up; z out of the face; mm; sagittal plane x = 0) and writes the transform.
//
// Inputs:  --in      surface mesh (PLY/STL/OBJ/OFF), any unit (mm, cm, m detected; --unit forces one)
//          --kind    head | respirator
// Outputs: --out       aligned surface (PLY, mm)
//          --transform 4×4 rigid transform as JSON (see align.h, align_json)
//
// Sample runs:
//   align --in build/cases/medium_onesize/head/repaired.ply --kind head --out aligned.ply --transform align.json
//   align --in ../shared/data/respirator-parts/Flex_Face_Seal_v9-M.stl --kind respirator --out r.ply -t r.json
#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "pipeline/atomic_write.h"
#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/progress.h"
#include "pipeline/units.h"
#include "pipeline/write_mesh.h"
#include "scan2cad/align.h"

int main(int argc, char** argv) {
  std::string in, out, transform_path, kind_name = "head", unit_name = "auto";
  int samples = 4000;
  pipeline::Cli cli("align", "Aligns a head or respirator surface into the paper's frame (x lateral, y up, z out of the face; mm).");
  cli.option("-i", "--in", &in, "input surface mesh (PLY/STL/OBJ/OFF), any unit", pipeline::required);
  cli.option("-k", "--kind", &kind_name, "head | respirator");
  cli.option("-u", "--unit", &unit_name, "unit of the input: auto, mm, cm, m, in");
  cli.option("-o", "--out", &out, "aligned surface (.ply, .off, .obj or .stl; mm)", pipeline::required);
  cli.option("-t", "--transform", &transform_path, "4x4 transform (JSON)", pipeline::required);
  cli.option("-s", "--samples", &samples, "surface samples for the symmetry search (its refinement uses at most 4999 of them)", 500, 100000);
  return pipeline::run_main(cli, argc, argv, [&] {
    pipeline::require_distinct_files({{"--in", in}, {"--out", out}, {"--transform", transform_path}});
    // 1. Options (run_main has logged them)
    const auto kind = scan2cad::parse_align_kind(kind_name);
    const pipeline::Unit unit = pipeline::parse_unit(unit_name);
    pipeline::require_extension("--out", out, pipeline::surface_mesh_extensions);
    pipeline::require_extension("--transform", transform_path, {".json"});
    pipeline::require_writable_outputs({out, transform_path});
    pipeline::Progress progress("align", 0);
    // 2. Load (unit detection: a head is ~250 mm, a respirator ~130 mm)
    progress.step("loading " + in);
    const double expected_mm = pipeline::expected_extent_mm(kind_name);
    pipeline::Unit unit_read = pipeline::Unit::mm;
    auto mesh = scan2cad::load_surface_any_unit(in, expected_mm, &unit_read, unit);
    const double scale = pipeline::mm_per_unit(unit_read);
    const double extent_mm = pipeline::largest_extent(mesh.points());
    pipeline::log("align", in + ": " + pipeline::describe_unit(unit_read, unit == pipeline::Unit::automatic, extent_mm,
                                                               kind_name, expected_mm));
    if (unit != pipeline::Unit::automatic)
      pipeline::require_forced_unit_plausible(in, unit_read, extent_mm, kind_name, expected_mm);
    // The unit is guessed without a few far vertices, which align would then take as the object's:
    // one vertex 3 m off failed 5 s later as "cannot tell up from down", one at 1e30 after 23 s.
    pipeline::require_real_size(in, extent_mm, kind_name);
    // 3. Align
    progress.step("symmetry plane and axes");
    scan2cad::AlignOptions opt;
    opt.kind = kind;
    opt.samples = samples;
    const auto res = pipeline::naming_file(in, [&] { return scan2cad::align(mesh, opt); });
    scan2cad::apply_transform(mesh, res.transform);
    // 4. Write atomically, both or neither
    pipeline::write_all_or_none(
        {{out, [&] { pipeline::write_surface_mesh(out, mesh); }},
         {transform_path, [&] { pipeline::write_text_atomic(transform_path, scan2cad::align_json(res, kind, scale)); }}});
    std::ostringstream summary;
    // What align did, which only align.json's matrix had told: a head turned 90 deg or moved 1 m
    // logged the same lines as one already in the frame (sweep J).
    const Eigen::AngleAxisd turn(Eigen::Matrix3d(res.transform.block<3, 3>(0, 0)));
    const Eigen::Vector3d shift = res.transform.block<3, 1>(0, 3);
    char moved[200];
    std::snprintf(moved, sizeof moved, "turned %.1f deg about (%.2f, %.2f, %.2f), then moved by (%.1f, %.1f, %.1f) mm",
                  turn.angle() * 180.0 / M_PI, turn.axis().x(), turn.axis().y(), turn.axis().z(), shift.x(), shift.y(),
                  shift.z());
    summary << moved << "; unit scale " << scale << ", symmetry RMS " << res.symmetry_rms_mm << " mm over "
            << std::lround(100 * res.symmetry_inliers) << "% of the surface";
    progress.finish(summary.str());
    return 0;
  });
}
