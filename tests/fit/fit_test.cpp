// Tests of scan2cad::remesh_parts / fit_deviation and the `fit` command line, on the NIOSH
// medium headform segmented with the landmarks fixture of tests/segment.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "layering/internal/segment_landmarks.h"
#include "layering/segment.h"
#include "pipeline/read_scan.h"
#include "pipeline/write_mesh.h"
#include "scan2cad/fit.h"
#include "../bad_input_message.h"
#include "../niosh_medium_ply.h"
#include "../last_line.h"
#include "../file_text.h"
#include "../run_command.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;

namespace {

const fs::path dir = scratch_dir() / "fit";

std::string niosh_medium_ply() { return ::niosh_medium_ply(dir); }

pipeline::SurfaceMesh segmented_medium() {
  pipeline::SurfaceMesh mesh = pipeline::read_surface_mesh(niosh_medium_ply());
  layering::segment_head(mesh, layering::internal::read_segment_landmarks(std::string(SOURCE_DIR) +
                                                                          "/tests/segment/niosh_medium_landmarks.json"));
  return mesh;
}

}  // namespace

TEST(remesh_parts, niosh_medium_fit_within_deviation_budget) {
  const pipeline::SurfaceMesh seg = segmented_medium();
  const pipeline::SurfaceMesh fitted = scan2cad::remesh_parts(seg, "head", 2.0);
  const auto dev = scan2cad::fit_deviation(seg, fitted, "head");
  ASSERT_EQ(dev.size(), 5u);
  for (const auto& d : dev) {
    SCOPED_TRACE(d.name);
    // Budget of the task (issue 3): 0.2 mm RMS, 1 mm max per part, both directions. Measured
    // against the same part (now outline_shift_mm): 0.02-0.05 mm RMS and 0.3-0.98 mm max (the max
    // sits on the most curved cells of the cuts). The outline may move by up to one fitted edge
    // (2 mm): its edges are chords of the cut.
    EXPECT_LE(d.rms_mm, 0.2);
    EXPECT_LE(d.max_mm, 1.0);
    EXPECT_LE(d.outline_shift_mm, 2.0);
    EXPECT_LE(d.max_mm, d.outline_shift_mm);  // the whole surface is nearer than its same part
    EXPECT_GT(d.samples, 1000u);
  }
  // The fitted surface stays closed and keeps one connected disk per part.
  EXPECT_TRUE(CGAL::is_closed(fitted));
  for (int label = 0; label <= 4; ++label) {
    SCOPED_TRACE(label);
    const auto s = layering::part_stats(fitted, label);
    EXPECT_EQ(s.euler, 1);
    EXPECT_EQ(s.boundary_loops, 1);
  }
}

// segment leaves each part one connected piece. Labels scrambled face by face passed fit, and
// surface_mesh then ran for over 11 minutes; one stray face of another part is refused alike.
TEST(check_parts, a_part_in_more_than_one_piece_is_refused) {
  pipeline::SurfaceMesh seg = segmented_medium();
  EXPECT_NO_THROW(scan2cad::check_parts(seg, "head"));
  auto part = seg.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
  const auto message = [](const pipeline::SurfaceMesh& mesh) {
    return bad_input_message([&] { scan2cad::check_parts(mesh, "head"); });
  };
  // one forehead face (with a forehead face on each side) made chin: chin in two pieces
  pipeline::SurfaceMesh island = seg;
  auto island_part = island.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
  for (auto f : island.faces()) {
    bool inside = island_part[f] == 1;
    for (auto h : CGAL::halfedges_around_face(island.halfedge(f), island))
      inside = inside && island_part[island.face(island.opposite(h))] == 1;
    if (inside) {
      island_part[f] = 4;
      break;
    }
  }
  EXPECT_EQ(message(island),
            "parts: part chin is in 2 separate pieces, but segment makes each part one connected piece "
            "(labels scrambled or edited by hand?)");
  for (auto f : seg.faces()) part[f] = int(std::size_t(f) % 5);
  EXPECT_NE(message(seg).find("separate pieces"), std::string::npos) << message(seg);
}

TEST(fit_cli, writes_labelled_ply_and_rejects_unlabelled_or_metre_input) {
  const std::string plain = niosh_medium_ply();
  const std::string seg = (dir / "seg.ply").string(), out = (dir / "fitted.ply").string();
  pipeline::write_surface_mesh(seg, segmented_medium());
  const std::string fit = std::string(BIN_DIR) + "/fit";
  const std::string log = (dir / "log.txt").string();
  EXPECT_EQ(run_command(fit + " --in " + seg + " --out " + out + " 2>" + log), 0);
  EXPECT_EQ(file_text(log).find("warning"), std::string::npos) << file_text(log);
  // A coarse edge: the same exit, and a warning for each part farther than 1 mm from the input.
  EXPECT_EQ(run_command(fit + " --in " + seg + " --edge 15 --out " + (dir / "coarse.ply").string() + " 2>" + log), 0);
  EXPECT_NE(file_text(log).find("fit: warning: forehead is up to "), std::string::npos) << file_text(log);
  EXPECT_NE(file_text(log).find(" mm off the input, over 1 mm (a shorter --edge follows it closer)"), std::string::npos);
  const pipeline::SurfaceMesh back = pipeline::read_surface_mesh(out);
  EXPECT_TRUE((back.property_map<pipeline::FaceIndex, int>(pipeline::part_property).second));
  // No "part" property: bad input (exit 2), no output file.
  const std::string bad = (dir / "bad.ply").string();
  EXPECT_EQ(run_command(fit + " --in " + plain + " --out " + bad + " 2>/dev/null"), 2);
  EXPECT_FALSE(fs::exists(bad));
  // Only part 0, which is a respirator's label (and a head's back_of_head): a head with no face
  // was fitted; now one line names the file and the missing part, exit 2.
  pipeline::SurfaceMesh one_part = segmented_medium();
  auto part = one_part.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
  for (auto f : one_part.faces()) part[f] = 0;
  const std::string respirator_like = (dir / "one_part.ply").string(), err = (dir / "err.txt").string();
  pipeline::write_surface_mesh(respirator_like, one_part);
  EXPECT_EQ(run_command(fit + " --in " + respirator_like + " --kind head --out " + bad + " 2>" + err), 2);
  EXPECT_EQ(last_line_of(err), "fit: " + respirator_like + ": parts: no face of part forehead: a segmented head has all five (is this a respirator?)");
  EXPECT_FALSE(fs::exists(bad));
  // The head in metres: fit wrote a 10-triangle "fit" with exit 0; now one line names the file.
  pipeline::SurfaceMesh in_metres = segmented_medium();
  for (auto v : in_metres.vertices()) in_metres.point(v) = CGAL::ORIGIN + (in_metres.point(v) - CGAL::ORIGIN) * 1e-3;
  const std::string metres = (dir / "metres.ply").string();
  pipeline::write_surface_mesh(metres, in_metres);
  EXPECT_EQ(run_command(fit + " --in " + metres + " --out " + bad + " 2>" + err), 2);
  const std::string line = last_line_of(err);
  EXPECT_EQ(line.rfind("fit: " + metres + ": largest extent 0.2", 0), 0u) << line;
  EXPECT_NE(line.find("but a head is about 250 mm: this stage reads mm only"), std::string::npos) << line;
  EXPECT_FALSE(fs::exists(bad));
  // An edge within the option's range but far below the head's scale ran for minutes past 1 GB;
  // now a usage error before any work (NIOSH medium, ~168,000 mm2: ~4 million triangles).
  EXPECT_EQ(run_command(fit + " --in " + seg + " --edge 0.3 --out " + bad + " 2>" + err), 1);
  const std::string edge_line = last_line_of(err);
  EXPECT_EQ(edge_line.rfind("fit: --edge 0.3 mm would make ~", 0), 0u) << edge_line;
  EXPECT_NE(edge_line.find("triangles on this "), std::string::npos) << edge_line;
  EXPECT_NE(edge_line.find(" mm2 surface, more than 1 million: choose a longer edge"), std::string::npos) << edge_line;
  EXPECT_FALSE(fs::exists(bad));
}

// Cheek labels swapped by hand were fitted, layered and assembled with the left cheek on the
// subject's right (exit 0); a part label of another type was reported as missing.
TEST(check_parts, cheeks_on_the_wrong_sides_and_a_label_of_another_type_are_refused) {
  pipeline::SurfaceMesh seg = segmented_medium();
  auto part = seg.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
  for (auto f : seg.faces())
    if (part[f] == 2 || part[f] == 3) part[f] = 5 - part[f];
  const std::string message = bad_input_message([&] { scan2cad::check_parts(seg, "head"); });
  EXPECT_EQ(message.rfind("parts: part left_cheek lies at mean x = -", 0), 0u) << message;
  EXPECT_NE(message.find("mm, on the subject's right (+x is the left in align's frame): cheek labels swapped?"),
            std::string::npos)
      << message;
  pipeline::SurfaceMesh typed = segmented_medium();
  auto labels = typed.property_map<pipeline::FaceIndex, int>(pipeline::part_property).first;
  typed.remove_property_map(labels);
  typed.add_property_map<pipeline::FaceIndex, float>(pipeline::part_property, 0.0f);
  EXPECT_EQ(bad_input_message([&] { scan2cad::check_parts(typed, "head"); }),
            "parts: face property \"part\" is not an int (segment writes int labels)");
}
