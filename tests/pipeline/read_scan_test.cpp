// read_scan on the real NIOSH headform and on small files with known defects.
#include <gtest/gtest.h>

#include <CGAL/boost/graph/helpers.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "pipeline/cli.h"
#include "pipeline/error.h"
#include "pipeline/read_scan.h"
#include "pipeline/soup_to_mesh.h"
#include "pipeline/write_mesh.h"
#include "../bad_input_message.h"
#include "../file_text.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;

namespace {

pipeline::ErrorKind error_kind_of(const std::string& path) {
  try {
    pipeline::read_scan(path);
  } catch (const pipeline::Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << "message names the file: " << e.what();
    return e.kind;
  }
  return pipeline::ErrorKind::usage;  // no error: the caller's expectation fails
}

}  // namespace

TEST(read_scan, reads_niosh_medium_stl_in_mm) {
  const std::string path = std::string(SHARED_DATA_DIR) + "/headforms/NIOSH_medium_20k.stl";
  const auto scan = pipeline::read_scan(path);
  ASSERT_TRUE(scan.is_mesh);
  EXPECT_EQ(scan.unit, pipeline::Unit::mm);
  EXPECT_EQ(scan.soup.polygons.size(), 20146u);
  // A closed triangle mesh has V = F/2 + 2: the corners STL stores per facet are merged.
  EXPECT_EQ(scan.soup.points.size(), 20146u / 2 + 2);
  EXPECT_NEAR(pipeline::largest_extent(scan.soup.points), 285.7, 0.5);
}

TEST(read_scan, scales_a_head_written_in_metres) {
  const std::string path = std::string(SHARED_DATA_DIR) + "/headforms/NIOSH_medium_20k.stl";
  auto scan = pipeline::read_scan(path);
  pipeline::PointCloud c;
  for (const auto& p : scan.soup.points) c.points.emplace_back(p.x() / 1000, p.y() / 1000, p.z() / 1000);
  const std::string m = (scratch_dir() / "head_m.xyz").string();
  pipeline::write_point_cloud(m, c);
  const auto back = pipeline::read_scan(m);
  EXPECT_EQ(back.unit, pipeline::Unit::m);
  EXPECT_NEAR(pipeline::largest_extent(back.cloud.points), 285.7, 0.5);
}

TEST(read_scan, bad_files_give_bad_input_naming_the_file) {
  using pipeline::ErrorKind;
  EXPECT_EQ(error_kind_of("/nonexistent/head.ply"), ErrorKind::bad_input);
  EXPECT_EQ(error_kind_of(scratch_file("empty.ply", "")), ErrorKind::bad_input);
  EXPECT_EQ(error_kind_of(scratch_file("text.stl", "this is not a mesh\n")), ErrorKind::bad_input);
  EXPECT_EQ(error_kind_of(scratch_file("text.ply", "hello world\n")), ErrorKind::bad_input);
  EXPECT_EQ(error_kind_of(scratch_file("nan.xyz", "0 0 0\n100 0 0\nnan 1 2\n0 200 0\n")), ErrorKind::bad_input);
  EXPECT_EQ(error_kind_of(scratch_file("garbled.xyz", "0 0 0\n100 x 0\n")), ErrorKind::bad_input);
  EXPECT_EQ(error_kind_of(scratch_file("huge.xyz", "0 0 0\n9e6 0 0\n0 9e6 0\n")), ErrorKind::bad_input);
  EXPECT_EQ(error_kind_of(scratch_file("scan.doc", "0 0 0\n")), ErrorKind::bad_input);
}

TEST(read_scan, truncated_binary_stl_and_ply_are_rejected) {
  const std::string stl = std::string(SHARED_DATA_DIR) + "/headforms/NIOSH_medium_20k.stl";
  const std::string bytes = file_text(stl);
  EXPECT_EQ(error_kind_of(scratch_file("cut.stl", bytes.substr(0, bytes.size() / 2))), pipeline::ErrorKind::bad_input);

  pipeline::PointCloud c;
  for (int i = 0; i < 1000; ++i) c.points.emplace_back(i * 0.2, (i % 10) * 20.0, (i % 7) * 30.0);
  const std::string ply = (scratch_dir() / "full.ply").string();
  pipeline::write_point_cloud(ply, c);
  const std::string pbytes = file_text(ply);
  EXPECT_EQ(error_kind_of(scratch_file("cut.ply", pbytes.substr(0, pbytes.size() / 2))), pipeline::ErrorKind::bad_input);
}

// A header count lowered below the data (hand-edited, or a writer that counted wrong): CGAL stops
// after the declared elements, and a 1,000-point scan declared as 500 was read as 500 points with
// exit 0. Binary and ASCII are refused, naming the file; a final newline after the data is not.
TEST(read_scan, data_beyond_the_counts_of_the_header_is_refused) {
  pipeline::PointCloud c;
  for (int i = 0; i < 1000; ++i) c.points.emplace_back(i * 0.2, (i % 10) * 20.0, (i % 7) * 30.0);
  const std::string ply = (scratch_dir() / "thousand.ply").string();
  pipeline::write_point_cloud(ply, c);
  const std::string bytes = file_text(ply);
  ASSERT_NE(bytes.find("element vertex 1000\n"), std::string::npos);
  std::string lowered = bytes;
  lowered.replace(lowered.find("element vertex 1000\n"), 20, "element vertex 500\n");
  const std::string low = scratch_file("lowered.ply", lowered);
  const std::string message = bad_input_message([&] { pipeline::read_scan(low); });  // 500 points of 3 doubles
  EXPECT_EQ(message.rfind(low + ": ", 0), 0u) << message;
  EXPECT_EQ(message, low + ": 12000 bytes after the elements its header declares: a count in the header is too small, or "
                     "data was appended (damaged or hand-edited file?)");
  EXPECT_EQ(pipeline::read_scan(scratch_file("newline.ply", bytes + "\n")).cloud.points.size(), 1000u);

  const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string ascii = header + "0 0 0\n100 0 0\n0 100 0\n3 0 1 2\n";
  const std::string extra_face = scratch_file("extra_face.ply", ascii + "3 2 1 0\n");
  EXPECT_NE(bad_input_message([&] { pipeline::read_scan(extra_face); }).find("bytes after the elements"),
            std::string::npos);
  EXPECT_NE(bad_input_message([&] { pipeline::read_surface_mesh(extra_face); }).find("bytes after the elements"),
            std::string::npos);
  pipeline::ScanReadOptions mm;
  mm.unit = pipeline::Unit::mm;
  EXPECT_EQ(pipeline::read_scan(scratch_file("blank_tail.ply", ascii + "\n  \n"), mm).soup.polygons.size(), 1u);

  // the same in an OFF: a face count lowered to 10,000 of NIOSH's 20,146 faces, and repair made a
  // 100 mm blob of what was read, with exit 0
  const std::string off = "OFF\n4 2 0\n0 0 0\n100 0 0\n0 100 0\n100 100 0\n3 0 1 2\n3 1 3 2\n";
  EXPECT_EQ(pipeline::read_scan(scratch_file("two.off", off + "\n"), mm).soup.polygons.size(), 2u);
  std::string one = off;
  const std::string low_off = scratch_file("lowered.off", one.replace(one.find("4 2 0"), 5, "4 1 0"));
  EXPECT_EQ(bad_input_message([&] { pipeline::read_scan(low_off, mm); }),
            low_off + ": 8 bytes after the elements its header declares: a count in the header is too small, or data "
                      "was appended (damaged or hand-edited file?)");
}

// Face indices of 16 or 8 bits are valid PLY, which CGAL's reader refuses: they were reported as
// "unreadable or truncated PLY", then named ("convert the file"). They are read (through assimp),
// ASCII and binary, by read_scan and read_surface_mesh, as the same triangles as 32-bit ones.
TEST(read_scan, a_ply_with_8_or_16_bit_face_indices_is_read) {
  const std::string vertices = "0 0 0\n100 0 0\n0 100 0\n0 0 100\n";
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const auto header = [](const std::string& format, const std::string& type) {
    return "ply\nformat " + format + " 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 4\nproperty list uchar " + type + " vertex_indices\nend_header\n";
  };
  const auto ascii = [&](const std::string& type) {
    std::string text = header("ascii", type) + vertices;
    for (const auto& f : faces) text += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
    return scratch_file("indices_" + type + ".ply", text);
  };
  // The same in binary, in either byte order, with 16-bit indices.
  const auto binary = [&](bool big_endian) {
    std::string bytes = header(big_endian ? "binary_big_endian" : "binary_little_endian", "ushort");
    const auto put = [&](std::uint32_t v, int n) {
      for (int k = 0; k < n; ++k) bytes.push_back(char(v >> (8 * (big_endian ? n - 1 - k : k))));
    };
    for (float c : {0.f, 0.f, 0.f, 100.f, 0.f, 0.f, 0.f, 100.f, 0.f, 0.f, 0.f, 100.f}) {
      std::uint32_t v;
      std::memcpy(&v, &c, 4);
      put(v, 4);
    }
    for (const auto& f : faces) {
      put(3, 1);
      for (int i : f) put(std::uint32_t(i), 2);
    }
    return bytes;
  };
  // Each triangle as its three corners from the lowest one on, in the triangle's own order: the
  // same surface whatever the vertex numbering.
  using Corners = std::array<std::array<double, 3>, 3>;
  const auto triangles = [](const pipeline::PolygonSoup& soup) {
    std::set<Corners> out;
    for (const auto& poly : soup.polygons) {
      Corners c;
      for (int k = 0; k < 3; ++k) {
        const auto& p = soup.points[poly[std::size_t(k)]];
        c[std::size_t(k)] = {p.x(), p.y(), p.z()};
      }
      std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
      out.insert(c);
    }
    return out;
  };
  const auto reference = triangles(pipeline::read_scan(ascii("int"), {pipeline::Unit::mm}).soup);
  ASSERT_EQ(reference.size(), 4u);
  for (const std::string& file : {ascii("ushort"), ascii("uchar"), ascii("short"), ascii("uint8"),
                                  scratch_file("indices_ushort_le.ply", binary(false)),
                                  scratch_file("indices_ushort_be.ply", binary(true))}) {
    EXPECT_EQ(triangles(pipeline::read_scan(file, {pipeline::Unit::mm}).soup), reference) << file;
    const pipeline::SurfaceMesh mesh = pipeline::read_surface_mesh(file);
    EXPECT_EQ(mesh.number_of_faces(), 4u) << file;
    EXPECT_TRUE(CGAL::is_closed(mesh)) << file;
  }
  for (const std::string type : {"uint", "int32", "uint32"})
    EXPECT_EQ(triangles(pipeline::read_scan(ascii(type), {pipeline::Unit::mm}).soup), reference) << type;
  // Checked as any PLY: assimp, which reads these files too, gave a cut binary file as 161,168
  // faces on one vertex, and an index past the vertices as a face on a vertex of its own.
  const std::string cut = scratch_file("indices_ushort_cut.ply", binary(false).substr(0, binary(false).size() - 5));
  EXPECT_EQ(bad_input_message([&] { pipeline::read_scan(cut, {pipeline::Unit::mm}); }),
            cut + ": truncated: its header declares 4 of element face, the file ends in number 4 (binary)");
  std::string past = binary(true);
  past[past.size() - 1] = 9;  // the last face's last index: 2 -> 9, of 4 vertices
  const std::string past_file = scratch_file("indices_ushort_past.ply", past);
  EXPECT_EQ(bad_input_message([&] { pipeline::read_scan(past_file, {pipeline::Unit::mm}); }),
            past_file + ": face 3 refers to vertex 9 of 4");
  EXPECT_EQ(bad_input_message([&] { pipeline::read_surface_mesh(past_file); }), past_file + ": face 3 refers to vertex 9 of 4");
}

// "x y z r g b" is as common a scanner export as "x y z nx ny nz": the colours were read as
// normals (255, 0, 0) and steered the orientation. Whole numbers in [0, 255], some above 1, are
// left out with a note; unit normals, axis-aligned ones (whole numbers up to 1) among them, stay.
TEST(read_scan, colour_columns_of_an_xyz_file_are_left_out_with_a_note) {
  pipeline::ScanReadOptions mm;
  mm.unit = pipeline::Unit::mm;
  const std::string points = "0 0 0 A\n100 0 0 B\n0 100 0 C\n0 0 100 D\n";
  const auto file = [&](const std::string& name, const std::vector<std::string>& extra) {
    std::string text = points;
    for (const char* mark : {"A", "B", "C", "D"}) text.replace(text.find(mark), 1, extra[std::size_t(mark[0] - 'A')]);
    return scratch_file(name, text);
  };
  const auto coloured = pipeline::read_scan(file("rgb.xyz", {"255 0 0", "0 255 0", "12 34 56", "200 200 200"}), mm);
  EXPECT_EQ(coloured.cloud.points.size(), 4u);
  EXPECT_TRUE(coloured.cloud.normals.empty());
  ASSERT_EQ(coloured.notes.size(), 1u);
  EXPECT_EQ(coloured.notes[0], "columns 4-6 left out (colours, intensity or other values; no three columns are unit "
                               "normals, so the normals are estimated)");
  for (const auto& [name, normals] :
       {std::pair<std::string, std::vector<std::string>>{"axes.xyz", {"0 0 1", "1 0 0", "0 1 0", "0 0 1"}},
        {"unit.xyz", {"0.6 0.8 0", "-1 0 0", "0 0.28 0.96", "0 0 -1"}}}) {
    const auto scan = pipeline::read_scan(file(name, normals), mm);
    EXPECT_EQ(scan.cloud.normals.size(), 4u) << name;
    EXPECT_TRUE(scan.notes.empty()) << name;
  }
  // colours as 0-1 floats were read as normals; CloudCompare's nine columns, colours then
  // normals, and normals then a scalar field, were refused or lost their normals
  const auto floats = pipeline::read_scan(file("rgb01.xyz", {"1 0 0", "0.5 0.5 0.5", "0 0 0", "0.2 0.9 0.1"}), mm);
  EXPECT_TRUE(floats.cloud.normals.empty());
  // skin tones as 0-1 floats, each row's length near 1 (0.95-1.20) but none a unit vector: a
  // tolerance of 0.5 for the 0.05 took them for normals, and no test had such rows (sweep N)
  const auto skin = pipeline::read_scan(
      file("skin01.xyz", {"0.8 0.6 0.5", "0.75 0.55 0.45", "0.7 0.5 0.4", "0.85 0.65 0.55"}), mm);
  EXPECT_TRUE(skin.cloud.normals.empty());
  EXPECT_EQ(skin.notes.size(), 1u);
  const auto nine = pipeline::read_scan(file("cc.xyz", {"255 0 0 0 0 1", "0 255 0 1 0 0", "1 2 3 0 1 0", "9 9 9 0 0 -1"}), mm);
  EXPECT_EQ(nine.cloud.normals.size(), 4u);
  EXPECT_EQ(nine.cloud.normals[1].x(), 1.0);
  EXPECT_EQ(nine.notes, std::vector<std::string>{"columns 4-6 left out (colours, intensity or other values; the "
                                                 "normals are columns 7-9)"});
  const auto scalar = pipeline::read_scan(file("scalar.xyz", {"0 0 1 7.5", "1 0 0 2", "0 1 0 0", "0 0 1 3"}), mm);
  EXPECT_EQ(scalar.cloud.normals.size(), 4u);
  EXPECT_EQ(scalar.notes, std::vector<std::string>{"column 7 left out (colours, intensity or other values; the "
                                                   "normals are columns 4-6)"});
}

// Scanner point exports beside "x y z [nx ny nz]": Leica PTS (a count line, then "x y z
// intensity [r g b]"), and "x,y,z" lines. Each was refused at its first line ("expected 3 or 6
// numbers"); a count that is not the file's, or lines of two kinds, are named.
TEST(read_scan, pts_exports_and_comma_separated_points_are_read) {
  pipeline::ScanReadOptions mm;
  mm.unit = pipeline::Unit::mm;
  const auto read = [&](const std::string& name, const std::string& text) { return pipeline::read_scan(scratch_file(name, text), mm); };
  const auto pts = read("leica.pts", "4\n0 0 0 -1200\n100 0 0 17\n0 100 0 5\n0 0 100 -3\n");
  EXPECT_EQ(pts.cloud.points.size(), 4u);
  EXPECT_TRUE(pts.cloud.normals.empty());
  EXPECT_EQ(pts.notes, std::vector<std::string>{"column 4 left out (colours, intensity or other values; no three "
                                                 "columns are unit normals, so the normals are estimated)"});
  const auto rgb = read("leica_rgb.pts", "4\n0 0 0 -1200 255 0 0\n100 0 0 17 0 0 0\n0 100 0 5 1 2 3\n0 0 100 -3 9 9 9\n");
  EXPECT_EQ(rgb.cloud.points.size(), 4u);
  ASSERT_EQ(rgb.notes.size(), 1u);
  EXPECT_EQ(rgb.notes[0].rfind("columns 4-7 left out (", 0), 0u) << rgb.notes[0];
  const auto commas = read("commas.xyz", "// X,Y,Z\n0,0,0\n100.5,0,0\n0,100,0\n0,0,100\n");
  ASSERT_EQ(commas.cloud.points.size(), 4u);
  EXPECT_EQ(commas.cloud.points[1].x(), 100.5);
  // Exports CloudCompare, spreadsheets and European locales write (the sweep of 2026-12-07 found
  // each refused): a header line of names, a byte order mark, "x, y, z", semicolons with decimal
  // commas, spaced columns with decimal commas, and .csv / .asc names.
  for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
           {"header.csv", "\xEF\xBB\xBFX,Y,Z\n0,0,0\n100.5,0,0\n0,100,0\n0,0,100\n"},
           {"spaced.xyz", "x y z\n0, 0, 0\n100.5, 0, 0\n0, 100, 0\n0, 0, 100\n"},
           {"semicolons.csv", "X;Y;Z\n0;0;0\n100,5;0;0\n0;100;0\n0;0;100\n"},
           {"decimal_comma.asc", "0 0 0\n100,5 0 0\n0 100 0\n0 0 100\n"}}) {
    const auto scan = read(name, text);
    ASSERT_EQ(scan.cloud.points.size(), 4u) << name;
    EXPECT_EQ(scan.cloud.points[1].x(), 100.5) << name;
  }
  const std::string short_pts = scratch_file("short.pts", "5\n0 0 0 1\n100 0 0 1\n0 100 0 1\n0 0 100 1\n");
  EXPECT_EQ(bad_input_message([&] { pipeline::read_scan(short_pts, mm); }),
            short_pts + ": its first line declares 5 points, the file holds 4 (truncated or edited?)");
  const std::string mixed = scratch_file("mixed.xyz", "0 0 0\n100 0 0 0 0 1\n0 100 0\n");
  EXPECT_EQ(bad_input_message([&] { pipeline::read_scan(mixed, mm); }),
            mixed + ": line 2 holds 6 numbers, line 1 held 3: one kind of line a file");
}

// A head in metres with one stray return 1.2 m off: no unit was found ("cannot tell the length
// unit"), the box being 1.2 m; the far point does not count (units.h, extent_without_far_points).
TEST(read_scan, a_stray_point_far_off_does_not_decide_the_unit) {
  std::string text;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j)
      text += pipeline::format_number(0.0143 * i) + " " + pipeline::format_number(0.012 * j) + " 0.1\n";  // 286 x 240 mm
  text += "0 0 1.2\n";
  const auto scan = pipeline::read_scan(scratch_file("stray_m.xyz", text));
  EXPECT_EQ(scan.unit, pipeline::Unit::m);
  EXPECT_EQ(scan.cloud.points.size(), 442u);
  EXPECT_NEAR(scan.extent_mm, 286, 1e-9);  // the size the unit was judged by, in mm; the box is 1200 mm
}

// OBJ lines indented or with tabs are valid OBJ: a face line written "f\t1\t3\t2" or indented was
// not seen (the mesh read as a cloud of its vertices, or by assimp with 2 of its 4 faces), and
// indented vertex lines made assimp refuse the file. A points-only OBJ keeps one "vn" a "v".
TEST(read_scan, obj_lines_indented_or_with_tabs_are_read) {
  pipeline::ScanReadOptions mm;
  mm.unit = pipeline::Unit::mm;
  const std::string tabs = "v 0 0 0\nv 100 0 0\nv 0 100 0\nv 0 0 100\nf\t1\t3\t2\n  f 1 2 4\nf 2 3 4\n\tf 1 4 3\n";
  const std::string indented = "  v 0 0 0\n\tv 100 0 0\n v 0 100 0\nv 0 0 100\n  f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
  for (const auto& [name, text] : {std::pair<std::string, std::string>{"tabs.obj", tabs}, {"indented.obj", indented}}) {
    const auto scan = pipeline::read_scan(scratch_file(name, text), mm);
    EXPECT_TRUE(scan.is_mesh) << name;
    EXPECT_EQ(scan.soup.polygons.size(), 4u) << name;
  }
  const auto points = pipeline::read_scan(scratch_file("vn.obj", "v 0 0 0\nv 100 0 0\n  v 0 100 0\nvn 0 0 1\nvn 1 0 0\nvn 0 1 0\n"), mm);
  EXPECT_FALSE(points.is_mesh);
  EXPECT_EQ(points.cloud.points.size(), 3u);
  EXPECT_EQ(points.cloud.normals.size(), 3u);
}

// An ASCII STL in upper case ("SOLID", "FACET NORMAL"; some CAD tools write it) was refused as
// "text that does not start with \"solid\"".
TEST(read_scan, an_upper_case_ascii_stl_is_read) {
  const auto scan = pipeline::read_scan(
      scratch_file("upper_case.stl", "SOLID PART\nFACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 100 0 0\n"
                                     "VERTEX 0 100 0\nENDLOOP\nENDFACET\nENDSOLID PART\n"),
      {pipeline::Unit::mm});
  EXPECT_TRUE(scan.is_mesh);
  EXPECT_EQ(scan.soup.polygons.size(), 1u);
  EXPECT_EQ(scan.soup.points.size(), 3u);
}

// An ending require_extension accepts in upper case is one the writers handle: a point cloud to
// "X.PLY" failed after the work ("unknown point cloud format '.PLY'"), since the writer compared
// the ending as written. Both formats round trip under an upper-case ending.
TEST(write_point_cloud, upper_case_endings_are_the_formats_of_their_lower_case) {
  pipeline::PointCloud c;
  for (int i = 0; i < 200; ++i) c.points.emplace_back(i * 0.5, (i % 10) * 20.0, (i % 7) * 30.0);
  for (const std::string name : {"upper.PLY", "upper.XYZ"}) {
    SCOPED_TRACE(name);
    const std::string path = (scratch_dir() / name).string();
    EXPECT_NO_THROW(pipeline::require_extension("--out", path, pipeline::point_cloud_extensions));
    pipeline::write_point_cloud(path, c);
    const pipeline::Scan back = pipeline::read_scan(path, {pipeline::Unit::mm});
    EXPECT_EQ(back.cloud.points.size(), c.points.size());
  }
  EXPECT_EQ(file_text(scratch_dir() / "upper.PLY").substr(0, 3), "ply");
}

// CGAL's text readers stop at "nan" as at a truncation; the error says which it was.
TEST(read_scan, nan_in_an_ascii_ply_or_off_is_named_as_such) {
  const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  auto message_of = [](const std::string& path) { return bad_input_message([&] { pipeline::read_scan(path); }); };
  const std::string nan_ply = scratch_file("nan_ascii.ply", header + "0 0 0\n100 0 0\n0 NaN 0\n3 0 1 2\n");
  EXPECT_EQ(message_of(nan_ply), nan_ply + ": line 12: a coordinate is NaN or infinite");
  const std::string inf_off = scratch_file("inf.off", "OFF\n3 1 0\n0 0 0\n-inf 0 0\n0 100 0\n3 0 1 2\n");
  EXPECT_EQ(message_of(inf_off), inf_off + ": line 4: a coordinate is NaN or infinite");
  const std::string cut_ply = scratch_file("cut_ascii.ply", header + "0 0 0\n100 0 0\n");
  EXPECT_EQ(message_of(cut_ply), cut_ply + ": truncated: its header declares 3 of element vertex, the file ends after 2 (line 11)");
  // a header comment with "inf" in it is not a coordinate
  const std::string commented = scratch_file("commented.ply", "ply\nformat ascii 1.0\ncomment inf nan information\n" +
                                                              header.substr(header.find("element")) + "0 0 0\n100 0 0\n");
  EXPECT_EQ(message_of(commented), commented + ": truncated: its header declares 3 of element vertex, the file ends after 2 (line 12)");
  const std::string last_word = scratch_file("nan_at_end.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 nan");
  EXPECT_EQ(message_of(last_word), last_word + ": line 5: a coordinate is NaN or infinite");
  // A count the file cannot hold: CGAL reserved it and the stage died of std::bad_alloc.
  const std::string huge = scratch_file("huge_count.off", "OFF\n2000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(message_of(huge), huge + ": the OFF header declares 2e+09 vertices and 1 faces, more than its 45 bytes can "
                                     "hold: truncated or damaged");
  const std::string commented_counts = scratch_file("commented_counts.off", "OFF\n# made by hand\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  pipeline::ScanReadOptions mm;
  mm.unit = pipeline::Unit::mm;
  EXPECT_EQ(pipeline::read_scan(commented_counts, mm).soup.polygons.size(), 1u);
}

// CGAL reads an ASCII PLY's body as one stream of numbers: a vertex with a number too many or too
// few was "unreadable or truncated PLY" or "N bytes after the elements", naming no line, and a file
// without its last face line was read without that face. Each is now named by its line.
TEST(read_scan, an_ascii_ply_line_that_differs_from_its_header_is_named) {
  const std::string header = "ply\nformat ascii 1.0\ncomment a tetrahedron\nelement vertex 4\nproperty float x\n"
                             "property float y\nproperty float z\nelement face 2\n"
                             "property list uchar int vertex_indices\nend_header\n";
  const auto message_of = [&](const std::string& name, const std::string& body) {
    const std::string path = scratch_file(name, header + body);
    const std::string m = bad_input_message([&] { pipeline::read_scan(path, {pipeline::Unit::mm}); });
    EXPECT_EQ(m, bad_input_message([&] { pipeline::read_surface_mesh(path); }));
    return m.substr(m.find(name) + name.size());
  };
  const std::string v = "0 0 0\n100 0 0\n0 100 0\n0 0 100\n", f = "3 0 1 2\n3 0 2 3\n";
  EXPECT_EQ(message_of("extra.ply", "0 0 0\n100 0 0 7\n0 100 0\n0 0 100\n" + f),
            ": line 12: vertex 2 holds 4 numbers, its header declares 3 (hand-edited or damaged file?)");
  EXPECT_EQ(message_of("fewer.ply", "0 0 0\n100 0\n0 100 0\n0 0 100\n" + f),
            ": line 12: vertex 2 holds 2 numbers, its header declares 3 (hand-edited or damaged file?)");
  EXPECT_EQ(message_of("face.ply", v + "3 0 1 2\n3 0 2 3 1\n"),
            ": line 16: face 2 holds 5 numbers, its header declares 4 (hand-edited or damaged file?)");
  EXPECT_EQ(message_of("word.ply", "0 0 0\n100 0 0\n0 abc 0\n0 0 100\n" + f), ": line 13: 'abc' in vertex 3 is not a number");
  EXPECT_EQ(message_of("last.ply", v + "3 0 1 2\n"),
            ": truncated: its header declares 2 of element face, the file ends after 1 (line 15)");
  // blank lines and CRLF endings are read
  const std::string crlf = scratch_file("crlf.ply", header + "0 0 0\r\n100 0 0\r\n\n0 100 0\n0 0 100\n" + f);
  EXPECT_EQ(pipeline::read_scan(crlf, {pipeline::Unit::mm}).soup.polygons.size(), 2u);
}

// A later stage's input that repair has not made manifold is named as such, apart from a broken
// file: CGAL's reader fails alike on both, and the message said "unreadable, truncated or
// non-manifold".
TEST(read_surface_mesh, tells_a_non_manifold_ply_from_a_truncated_one) {
  auto message_of = [](const std::string& path) {
    return bad_input_message([&] { pipeline::read_surface_mesh(path); });
  };
  const std::string header = "ply\nformat ascii 1.0\nelement vertex 5\nproperty double x\nproperty double y\n"
                             "property double z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string points = "0 0 0\n100 0 0\n50 80 0\n50 -80 0\n50 0 80\n";
  // three triangles on the edge 0-1: a fin
  const std::string fin = scratch_file("fin.ply", header + points + "3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  EXPECT_EQ(message_of(fin), fin + ": not a 2-manifold polygon mesh (3 faces read; run repair first)");
  const std::string cut = scratch_file("cut_mesh.ply", header + points + "3 0 1 2\n3 1 0");
  EXPECT_EQ(message_of(cut), cut + ": line 16: face 2 holds 3 numbers, its header declares 4 (hand-edited or damaged file?)");
  const std::string two = scratch_file("two.ply", header + points + "3 0 1 2\n3 1 0 3\n3 2 1 4\n");
  EXPECT_EQ(message_of(two), "no error");
  // A face index past the vertices (a corrupted file) crashed CGAL's Surface_mesh reader, and so
  // landmarks, segment, fit and surface_mesh. A negative index is shown as the file holds it.
  const std::string past = scratch_file("past.ply", header + points + "3 0 1 2\n3 1 0 3\n3 2 1 9\n");
  EXPECT_EQ(message_of(past), past + ": face 2 refers to vertex 9 of 5");
  std::string binary = "ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\n"
                       "property float y\nproperty float z\nelement face 3\n"
                       "property list uchar int vertex_indices\nend_header\n";
  const float xyz[5][3] = {{0, 0, 0}, {100, 0, 0}, {50, 80, 0}, {50, -80, 0}, {50, 0, 80}};
  binary.append(reinterpret_cast<const char*>(xyz), sizeof xyz);  // this test runs on little-endian x86
  const std::int32_t faces[3][3] = {{0, 1, 2}, {1, -7, 3}, {2, 1, 4}};
  for (const auto& f : faces) {
    binary.push_back(char(3));
    binary.append(reinterpret_cast<const char*>(f), sizeof f);
  }
  const std::string negative = scratch_file("negative.ply", binary);
  EXPECT_EQ(message_of(negative), negative + ": face 1 refers to vertex -7 of 5");
  // A face list count of -3 (read as a huge unsigned size) ended the stage as an internal error
  // naming no file: bad input, for a scan and for a later stage's mesh alike.
  std::string damaged = "ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\n"
                        "property float y\nproperty float z\nelement face 1\n"
                        "property list int int vertex_indices\nend_header\n";
  damaged.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  const std::int32_t minus_three[4] = {-3, 0, 1, 2};
  damaged.append(reinterpret_cast<const char*>(minus_three), sizeof minus_three);
  const std::string list_count = scratch_file("list_count.ply", damaged);
  EXPECT_EQ(message_of(list_count), list_count + ": damaged PLY: it declares a list or element larger than memory can hold");
  EXPECT_EQ(bad_input_message([&] { pipeline::read_scan(list_count); }),
            list_count + ": damaged PLY: it declares a list or element larger than memory can hold");
  // Vertices moved onto another (an edited file): zero-area faces crashed surface_mesh's
  // remeshing and made segment assert or cut absurd parts.
  const std::string collapsed = scratch_file(
      "collapsed.ply", header + "0 0 0\n100 0 0\n50 80 0\n50 -80 0\n100 0 0\n3 0 1 2\n3 1 0 3\n3 2 1 4\n");
  EXPECT_EQ(message_of(collapsed), collapsed + ": 1 degenerate face (zero area; the first is face 2): run repair first");
  // Faces listed before the vertices (valid PLY) crashed CGAL's Surface_mesh reader.
  const std::string faces_first = scratch_file(
      "faces_first.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
                         "element vertex 3\nproperty double x\nproperty double y\nproperty double z\nend_header\n"
                         "3 0 1 2\n0 0 0\n100 0 0\n0 100 0\n");
  EXPECT_EQ(message_of(faces_first), faces_first + ": its faces come before its vertices: a mesh a stage wrote lists vertices first");
}

// A scanner's or MeshLab's quads: soup_to_mesh (align's loader, repair) cuts them into triangles;
// a later stage's mesh must be triangles already. The stages' AABB trees, samplers and ray grids
// read three corners of a face: of a 10 mm square they saw half, points 4.95 mm inside it missed
// (sweep S).
TEST(soup_to_mesh, cuts_quads_into_triangles_and_read_surface_mesh_refuses_them) {
  pipeline::PolygonSoup cube;
  for (int i = 0; i < 8; ++i) cube.points.emplace_back(10.0 * (i & 1), 10.0 * ((i >> 1) & 1), 10.0 * ((i >> 2) & 1));
  cube.polygons = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  pipeline::SoupStats stats;
  const pipeline::SurfaceMesh mesh = pipeline::soup_to_mesh(cube, &stats);
  EXPECT_EQ(mesh.number_of_faces(), 12u);
  for (auto f : mesh.faces()) EXPECT_EQ(mesh.degree(f), 3u);
  EXPECT_TRUE(CGAL::is_closed(mesh));
  EXPECT_EQ(stats.polygons_removed, 0u);
  std::string off = "OFF\n8 6 0\n";
  for (const auto& p : cube.points) off += std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
  for (const auto& q : cube.polygons) off += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " + std::to_string(q[3]) + "\n";
  const std::string quads = scratch_file("quads.off", off);
  EXPECT_EQ(bad_input_message([&] { pipeline::read_surface_mesh(quads); }),
            quads + ": face 0 has 4 corners, expected triangles (a stage's output; run repair first)");
}

// A vertex no face uses (a scanner's marker far off) decided the unit: a 200 mm head with one at
// 100 m read as a head in metres... scaled to 1e5 m. Such vertices are dropped before the size is
// measured, by read_scan and by read_surface_mesh.
TEST(read_scan, vertices_no_face_uses_are_dropped_before_the_unit_is_detected) {
  const std::string off = scratch_file("stray.off", "OFF\n4 1 0\n0 0 0\n200 0 0\n0 200 0\n100000 0 0\n3 0 1 2\n");
  const pipeline::Scan scan = pipeline::read_scan(off);
  EXPECT_EQ(scan.unit, pipeline::Unit::mm);
  EXPECT_EQ(scan.soup.points.size(), 3u);
  EXPECT_EQ(pipeline::largest_extent(scan.soup.points), 200.0);
  const std::string ply = scratch_file(
      "stray.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
                   "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                   "100000 0 0\n0 0 0\n200 0 0\n0 200 0\n3 1 2 3\n");
  const pipeline::SurfaceMesh mesh = pipeline::read_surface_mesh(ply);
  EXPECT_EQ(mesh.number_of_vertices(), 3u);
  EXPECT_EQ(pipeline::largest_extent(mesh.points()), 200.0);
}

// A NaN normal reached Poisson, which failed as an algorithm error ("normals inconsistent?").
TEST(read_scan, a_nan_normal_is_bad_input_naming_the_point) {
  pipeline::PointCloud c;
  for (int i = 0; i < 200; ++i) {
    c.points.emplace_back(i * 1.0, (i % 10) * 20.0, (i % 7) * 30.0);
    c.normals.emplace_back(0, 0, 1);
  }
  c.normals[17] = pipeline::Vector(0, std::nan(""), 1);
  const std::string ply = (scratch_dir() / "nan_normal.ply").string();
  pipeline::write_point_cloud(ply, c);
  EXPECT_EQ(bad_input_message([&] { pipeline::read_scan(ply); }, ply),
            "point 17 has a non-finite (NaN or infinite) normal");
}

// Point normals as other tools name them: PCL writes a PLY's normals as "normal_x normal_y
// normal_z" (often as float, with a curvature after them), and Geomview's NOFF gives them after
// each vertex. CGAL's readers took neither, so the normals were estimated again.
TEST(read_scan, pcl_ply_normals_and_noff_normals_are_read) {
  pipeline::ScanReadOptions mm;
  mm.unit = pipeline::Unit::mm;
  const std::array<std::array<float, 6>, 4> rows{{{0, 0, 0, 0, 0, 1},
                                                  {100, 0, 0, 1, 0, 0},
                                                  {0, 100, 0, 0, -1, 0},
                                                  {0, 0, 100, 0.6f, 0.8f, 0}}};
  const auto expect_normals = [&](const pipeline::Scan& scan, const std::string& name) {
    ASSERT_EQ(scan.cloud.points.size(), 4u) << name;
    ASSERT_EQ(scan.cloud.normals.size(), 4u) << name;
    for (std::size_t i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(scan.cloud.points[i][k], rows[i][std::size_t(k)]) << name << " point " << i;
        EXPECT_NEAR(scan.cloud.normals[i][k], rows[i][std::size_t(k) + 3], 1e-7) << name << " normal " << i;
      }
    EXPECT_TRUE(scan.notes.empty()) << name;
  };
  const std::string header_start = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n";
  for (const std::string names : {"nx ny nz", "normal_x normal_y normal_z"}) {
    std::istringstream words(names);
    std::string header = header_start, name;
    while (words >> name) header += "property float " + name + "\n";
    header += "property float curvature\nend_header\n";
    std::string text = header;
    for (const auto& r : rows) {
      for (float v : r) text += pipeline::format_number(v) + " ";
      text += "0.01\n";
    }
    expect_normals(pipeline::read_scan(scratch_file("ascii_" + names.substr(0, 2) + ".ply", text), mm), names);
    std::string binary = header;
    binary.replace(binary.find("ascii"), 5, "binary_little_endian");
    for (const auto& r : rows) {
      for (float v : r) binary.append(reinterpret_cast<const char*>(&v), sizeof v);
      const float curvature = 0.01f;
      binary.append(reinterpret_cast<const char*>(&curvature), sizeof curvature);
    }
    expect_normals(pipeline::read_scan(scratch_file("binary_" + names.substr(0, 2) + ".ply", binary), mm), names + " binary");
  }
  std::string noff = "NOFF\n# points with normals\n4 0 0\n";
  for (const auto& r : rows) {
    for (float v : r) noff += pipeline::format_number(v) + " ";
    noff += "\n";
  }
  expect_normals(pipeline::read_scan(scratch_file("points.off", noff), mm), "NOFF");
  // CGAL's point reader takes only a header line of its own; with the counts on it the points are
  // kept and the normals estimated, said in a note (CGAL's own complaint on std::cerr kept quiet)
  std::string one_line = noff;
  one_line.replace(0, one_line.find("4 0 0"), "NOFF ");
  const auto points_only = pipeline::read_scan(scratch_file("one_line.off", one_line), mm);
  EXPECT_EQ(points_only.cloud.points.size(), 4u);
  EXPECT_TRUE(points_only.cloud.normals.empty());
  EXPECT_EQ(points_only.notes, std::vector<std::string>{"its NOFF normals were not read (not one vertex a line), so they are estimated"});
  // a plain OFF point set has none
  const auto off = pipeline::read_scan(scratch_file("plain.off", "OFF\n4 0 0\n0 0 0\n100 0 0\n0 100 0\n0 0 100\n"), mm);
  EXPECT_EQ(off.cloud.points.size(), 4u);
  EXPECT_TRUE(off.cloud.normals.empty());
}
