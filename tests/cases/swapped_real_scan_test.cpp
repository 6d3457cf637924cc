// `make case=... HEADFORM_SCAN=...` with the real stage programs on a real head: the NIOSH large
// headform, scanned (80,000 points, 0.2 mm noise, 0.5 % outliers, two random holes) and written as
// an XYZ point cloud in metres, as a scanner might export it. Every stage from reconstruct to
// assemble runs on it in the case's own folder; the scan is read as metres, and the case ends in a
// model whose head is layered at about the paper's element count with the respirator 3 mm off
// the skin. cases_makefile_test checks Make's dependency graph with stand-ins; this checks that
// the stages, as Makefile.cases calls them, fit together on data that is not generated.
// About 75 s of CPU on this machine (fit of the 235,000-triangle head: 24 s, reconstruct: 17 s).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "pipeline/atomic_write.h"
#include "../last_line.h"
#include "../run_command.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;

TEST(swapped_real_scan, niosh_large_in_metres_runs_through_every_stage_to_the_model) {
  // A BUILD folder of its own, so the shared heads and respirators of build/ are not touched; its
  // bin/ is the real programs.
  const fs::path build = scratch_dir() / "build";
  fs::remove_all(build);
  fs::create_directories(build);
  fs::create_directory_symlink(BIN_DIR, build / "bin");

  const fs::path mm = scratch_dir() / "niosh_large_mm.xyz", metres = scratch_dir() / "niosh_large_m.xyz";
  ASSERT_EQ(run_command(std::string(BIN_DIR) + "/generate_scan --from-mesh " SHARED_DATA_DIR "/headforms/NIOSH_large_20k.stl" +
                        " --points 80000 --noise-mm 0.2 --outlier-fraction 0.005 --holes 2 --seed 5 --out " +
                        mm.string() + " 2> /dev/null"),
            0);
  {
    std::ifstream in(mm);
    std::ofstream out(metres);
    out.precision(7);
    out.setf(std::ios::fixed);
    for (double x, y, z; in >> x >> y >> z;) out << x / 1000 << " " << y / 1000 << " " << z / 1000 << "\n";
  }

  const fs::path log = scratch_dir() / "make.log";
  const int rc = run_command("make --no-print-directory -C " SOURCE_DIR
                             " -f Makefile.cases case=large_onesize HEADFORM_SCAN=" +
                             metres.string() + " BUILD=" + build.string() + " > " + log.string() + " 2>&1");
  const std::string text = pipeline::read_text(log.string());
  ASSERT_EQ(rc, 0) << text.substr(text.size() > 4000 ? text.size() - 4000 : 0);

  // Read as metres, processed in the case's own folder.
  EXPECT_NE(text.find("reconstruct: " + metres.string() + ": unit m (detected"), std::string::npos);
  const fs::path head = build / "cases/large_onesize/head";
  EXPECT_FALSE(fs::is_symlink(head));
  EXPECT_EQ(last_line(text),
            "case large_onesize: not yet part of the pipeline (next): stage-I/II simulation (solve)");
  EXPECT_NE(text.find("case large_onesize: up to date through the stages reconstruct repair align landmarks "
                      "segment fit surface_mesh layers straps assemble;"),
            std::string::npos);

  // The repaired head is closed, manifold and free of self-intersections; the layered head has the paper's size of model (13,570 wedges for
  // its medium head; a large head at the same edge length has a few per cent more or less) and
  // all 13 layer volumes.
  const auto repair = nlohmann::json::parse(pipeline::read_text((head / "repair_report.json").string()));
  EXPECT_TRUE(repair.at("closed").get<bool>()) << repair.dump();
  EXPECT_TRUE(repair.at("manifold").get<bool>());
  EXPECT_FALSE(repair.at("self_intersecting_after").get<bool>());
  const auto layers = nlohmann::json::parse(pipeline::read_text((head / "layers_report.json").string()));
  EXPECT_GT(layers.at("wedges").get<int>(), 11000);
  EXPECT_LT(layers.at("wedges").get<int>(), 16500);
  EXPECT_EQ(layers.at("volumes").size(), 13u);
  EXPECT_GE(layers.at("min_scaled_jacobian").get<double>(), 0.2);
  EXPECT_EQ(layers.at("intersecting_face_pairs").get<int>(), 0);

  // The model: respirator 3 mm off the skin (assemble's own check), nothing crossing.
  for (const char* f : {"model.msh", "stage1.json", "stage2.json", "straps.msh"})
    EXPECT_TRUE(fs::exists(build / "cases/large_onesize" / f)) << f;
  const auto at = text.find("assemble: " + (build / "cases/large_onesize/model.msh").string() + ": ");
  ASSERT_NE(at, std::string::npos);
  const std::string line = text.substr(at, text.find('\n', at) - at);
  EXPECT_NE(line.find("gap 3.0"), std::string::npos) << line;
  EXPECT_NE(line.find("; 0 intersecting face pairs"), std::string::npos) << line;
}
