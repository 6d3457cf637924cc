// `make case=... HEADFORM_SCAN=...` with the real stage programs on a real head: the NIOSH large
// headform, scanned (80,000 points, 0.2 mm noise, 0.5 % outliers, two random holes) and written as
// an XYZ point cloud in metres, as a scanner might export it. Every stage from reconstruct to
// assemble runs on it in the case's own folder; the scan is read as metres, and the case ends in a
// model whose head is layered at about the paper's element count with the respirator 3 mm off
// the skin. cases_makefile_test checks Make's dependency graph with stand-ins; this checks that
// the stages, as Makefile.cases calls them, fit together on data that is not generated.
// Then each stage gets the case's own files corrupted, one at a time, and must refuse them
// (expect_stages_refuse_corrupted_inputs below).
// About 75 s of CPU on this machine (fit of the 235,000-triangle head: 24 s, reconstruct: 17 s),
// and ~15 s for the corrupted inputs.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/atomic_write.h"
#include "../last_line.h"
#include "../run_command.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;

namespace {

// `text` cut to its first half: a copy or download that stopped.
std::string first_half(const std::string& text) { return text.substr(0, text.size() / 2); }

// A binary PLY of the stages (x, y, z as doubles, then faces whose first property is the
// uchar/int index list) with face 0's second index set to -7, as a flipped bit might leave it;
// "" when the file is not laid out so (the caller asserts on it, so a changed writer fails here).
std::string face_index_corrupted(const std::string& ply) {
  const std::size_t end = ply.find("end_header\n");
  if (end == std::string::npos) return "";
  const std::size_t body = end + 11;
  const std::string header = ply.substr(0, body);
  const std::size_t at = header.find("\nelement vertex "), face = header.find("\nelement face ");
  if (header.find("\nformat binary_little_endian 1.0\n") == std::string::npos || at == std::string::npos ||
      face == std::string::npos ||
      header.find("\nproperty double x\nproperty double y\nproperty double z\nelement face ") == std::string::npos ||
      header.compare(header.find('\n', face + 1), 40, "\nproperty list uchar int vertex_indices\n") != 0)
    return "";
  const std::size_t vertices = std::stoul(header.substr(at + 16, header.find('\n', at + 16) - at - 16));
  if (ply.size() < body + 24 * vertices + 13) return "";
  std::string out = ply;
  const std::int32_t index = -7;
  std::memcpy(&out[body + 24 * vertices + 1 + 4], &index, 4);
  return out;
}

// A .msh whose $Nodes section lost its closing line: gmsh reads it without a word and without
// its elements.
std::string end_nodes_removed(std::string msh) {
  const std::size_t at = msh.find("$EndNodes\n");
  EXPECT_NE(at, std::string::npos);
  return at == std::string::npos ? msh : msh.erase(at, 10);
}

// Each stage after reconstruct, run as Makefile.cases runs it (solve as its README does) on the case in `case_dir`, with one
// of its inputs corrupted at a time: cut in half; for a PLY, a face index past the vertices (it
// crashed landmarks, segment, fit and surface_mesh); for a .msh, $EndNodes removed (layers and
// assemble wrote their outputs with exit 0). Each must exit 2 with its last stderr line naming
// the corrupted file, and write nothing.
void expect_stages_refuse_corrupted_inputs(const fs::path& case_dir) {
  const std::string head = (case_dir / "head").string() + "/", resp = (case_dir / "respirator").string() + "/",
                    cased = case_dir.string() + "/", materials = SOURCE_DIR "/data/materials.json";
  const fs::path out_dir = scratch_dir() / "corrupted";
  fs::create_directories(out_dir);
  const std::string out = out_dir.string() + "/";
  struct Stage {
    std::string program;
    std::vector<std::pair<std::string, std::string>> inputs;  // option, file
    std::string outputs;                                      // the output options, as Makefile.cases gives them
    std::vector<std::string> output_files;
  };
  const Stage stages[] = {
      {"repair", {{"--in", head + "reconstructed.ply"}}, "--out " + out + "r.ply --report " + out + "r.json",
       {"r.ply", "r.json"}},
      {"align", {{"--in", head + "repaired.ply"}}, "--out " + out + "a.ply --transform " + out + "a.json",
       {"a.ply", "a.json"}},
      {"landmarks", {{"--in", head + "aligned.ply"}}, "--out " + out + "l.json", {"l.json"}},
      {"segment", {{"--in", head + "aligned.ply"}, {"--landmarks", head + "landmarks.json"}}, "--out " + out + "s.ply",
       {"s.ply"}},
      {"fit", {{"--in", head + "segmented.ply"}}, "--out " + out + "f.ply", {"f.ply"}},
      {"surface_mesh", {{"--in", head + "fitted.ply"}}, "--out " + out + "m.msh", {"m.msh"}},
      {"layers", {{"--in", head + "surface.msh"}, {"--materials", materials}},
       "--out " + out + "y.msh --report " + out + "y.json", {"y.msh", "y.json"}},
      {"straps", {{"--head", head + "layers.msh"}, {"--landmarks", head + "landmarks.json"},
                  {"--respirator", resp + "layers.msh"}},
       "--out " + out + "t.msh", {"t.msh"}},
      {"assemble", {{"--head", head + "layers.msh"}, {"--respirator", resp + "layers.msh"},
                    {"--straps", cased + "straps.msh"}, {"--landmarks", head + "landmarks.json"},
                    {"--materials", materials}},
       "--out " + out + "model.msh --deck1 " + out + "d1.json --deck2 " + out + "d2.json",
       {"model.msh", "d1.json", "d2.json"}},
      {"solve", {{"--model", cased + "model.msh"}, {"--deck", cased + "stage1.json"}}, "--out-dir " + out + "solved",
       {"solved"}},
  };
  int runs = 0;
  for (const Stage& stage : stages)
    for (std::size_t k = 0; k < stage.inputs.size(); ++k) {
      const std::string& file = stage.inputs[k].second;
      const std::string text = pipeline::read_text(file), ext = fs::path(file).extension().string();
      std::vector<std::pair<std::string, std::string>> corrupted = {{"cut", first_half(text)}};
      if (ext == ".ply") {
        corrupted.push_back({"face_index", face_index_corrupted(text)});
        ASSERT_FALSE(corrupted.back().second.empty()) << file << ": not the binary PLY layout the stages write";
      }
      if (ext == ".msh") corrupted.push_back({"no_end_nodes", end_nodes_removed(text)});
      for (const auto& [how, bytes] : corrupted) {
        const std::string bad = out + how + "_" + fs::path(file).filename().string();
        pipeline::write_text_atomic(bad, bytes);
        std::string command = std::string(BIN_DIR) + "/" + stage.program;
        for (std::size_t i = 0; i < stage.inputs.size(); ++i)
          command += " " + stage.inputs[i].first + " " + (i == k ? bad : stage.inputs[i].second);
        const std::string log = out + "stderr.txt";
        const int rc = run_command(command + " " + stage.outputs + " > /dev/null 2> " + log);
        const std::string what = stage.program + " " + stage.inputs[k].first + " " + how;
        ++runs;
        EXPECT_EQ(rc, 2) << what;
        const std::string line = last_line_of(log);
        EXPECT_EQ(line.rfind(stage.program + ": " + bad + ": ", 0), 0u) << what << ": " << line;
        for (const auto& o : stage.output_files) EXPECT_FALSE(fs::exists(out + o)) << what << " wrote " << o;
        fs::remove(bad);
      }
    }
  EXPECT_EQ(runs, 32);
}

}  // namespace

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
  EXPECT_NE(text.find("case large_onesize: done through the stages reconstruct repair align landmarks "
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

  expect_stages_refuse_corrupted_inputs(build / "cases/large_onesize");
}
