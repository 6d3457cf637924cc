#include "pipeline/read_scan.h"

#include <CGAL/IO/PLY.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/IO/read_points.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/property_map.h>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <new>
#include <sstream>
#include <stdexcept>

#include "pipeline/error.h"
#include "pipeline/lower_extension.h"
#include "pipeline/require_file.h"

namespace fs = std::filesystem;
namespace PMP = CGAL::Polygon_mesh_processing;

namespace pipeline {

namespace {

// `xyz` are points or normals; the error names the `element` and what of it is not finite.
template <class Xyz>
void check_finite(const std::vector<Xyz>& xyz, const std::string& path, const char* element, const char* what) {
  for (std::size_t i = 0; i < xyz.size(); ++i)
    if (!std::isfinite(xyz[i].x()) || !std::isfinite(xyz[i].y()) || !std::isfinite(xyz[i].z()))
      throw bad_input(path, std::string(element) + " " + std::to_string(i) + " has a non-finite (NaN or infinite) " + what);
}

// A corrupted binary file can hold any index; a negative 32-bit one reads as a huge size_t,
// so it is shown as the signed number the file holds.
void check_face_indices(const std::vector<std::vector<std::size_t>>& polygons, std::size_t n_points,
                        const std::string& path) {
  for (std::size_t f = 0; f < polygons.size(); ++f)
    for (std::size_t i : polygons[f])
      if (i >= n_points) {
        const std::string index = i > std::size_t(std::numeric_limits<std::int64_t>::max())
                                      ? std::to_string(std::int64_t(i))
                                      : std::to_string(i);
        throw bad_input(path, "face " + std::to_string(f) + " refers to vertex " + index + " of " +
                                  std::to_string(n_points));
      }
}

std::string first_bytes(const std::string& path, std::size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string s(n, '\0');
  in.read(&s[0], std::streamsize(n));
  s.resize(std::size_t(in.gcount()));
  return s;
}

// A PLY header as far as the checks below need it: each element's name, count and properties in
// order. CGAL's reader parses the header itself but does not expose it.
struct PlyProperty {
  std::string name, type, index_type;  // type: a scalar's, or a list's count type; index_type: a list's item type
  bool is_list = false;
};
struct PlyElement {
  std::string name;
  double count = 0;
  std::vector<PlyProperty> properties;
};
struct PlyHeader {
  bool complete = false;  // end_header found and every element count parsed
  bool ascii = false, big_endian = false;
  std::size_t lines = 0;  // lines up to end_header
  std::vector<PlyElement> elements;
};

PlyHeader read_ply_header(std::istream& in) {
  PlyHeader h;
  for (std::string line; std::getline(in, line);) {
    ++h.lines;
    std::istringstream words(line);
    std::string key, a;
    words >> key >> a;
    if (key == "format") h.ascii = a == "ascii", h.big_endian = a == "binary_big_endian";
    if (key == "element") {
      PlyElement e{a, 0, {}};
      if (!(words >> e.count) || !(e.count >= 0)) return h;
      h.elements.push_back(e);
    }
    if (key == "property" && !h.elements.empty()) {
      PlyProperty p;
      p.is_list = a == "list";
      p.type = a;
      if (p.is_list) words >> p.type >> p.index_type;
      words >> p.name;
      h.elements.back().properties.push_back(p);
    }
    if (key == "end_header") {
      h.complete = true;
      return h;
    }
  }
  return h;
}

// An ASCII PLY holds each element on a line of its own, its properties in the header's order. CGAL
// reads the body as one stream of numbers, so a vertex with a number too many shifted everything
// after it ("unreadable or truncated PLY", or "bytes after the elements", naming no line), and a
// file missing its last face line was read without it. Names the first line that differs from
// the header, or the element where the file ends. Binary files and headers it cannot parse are
// left to CGAL's reader. `in` is `path` read up to the end of its header `h`.
void require_ascii_ply_lines_match_header(const std::string& path, std::istream& in, const PlyHeader& h) {
  if (!h.complete || !h.ascii) return;
  const auto number = [](const std::string& word, double* v) {
    char* end = nullptr;
    *v = std::strtod(word.c_str(), &end);
    return !word.empty() && *end == '\0';
  };
  std::size_t line_no = h.lines;
  std::string line;
  for (const PlyElement& e : h.elements)
    for (double i = 1; i <= e.count; ++i) {
      do {
        if (!std::getline(in, line))
          throw bad_input(path, "truncated: its header declares " + format_number(e.count) + " of element " + e.name +
                                    ", the file ends after " + format_number(i - 1) + " (line " +
                                    std::to_string(line_no) + ")");
        ++line_no;
      } while (line.find_first_not_of(" \t\r") == std::string::npos);
      std::istringstream words(line);
      std::vector<double> values;
      for (std::string word; words >> word;) {
        double v = 0;
        if (!number(word, &v))
          throw bad_input(path, "line " + std::to_string(line_no) + ": '" + word + "' in " + e.name + " " +
                                    format_number(i) + " is not a number");
        values.push_back(v);
      }
      std::size_t expected = 0;
      for (const PlyProperty& p : e.properties) {
        if (p.is_list) {
          const double n = expected < values.size() ? values[expected] : 0;
          if (!(n >= 0 && n == std::floor(n) && n < 1e6)) break;  // left to the size check below
          expected += std::size_t(n);
        }
        ++expected;
      }
      if (values.size() != expected)
        throw bad_input(path, "line " + std::to_string(line_no) + ": " + e.name + " " + format_number(i) + " holds " +
                                  std::to_string(values.size()) + " numbers, its header declares " +
                                  std::to_string(expected) + " (hand-edited or damaged file?)");
    }
}

// Why a text mesh that CGAL's reader refused is unusable. CGAL reads numbers with
// istream >> double, which stops at "nan" and "inf" as at a truncation, so a scanner's NaN
// (organised point clouds mark missing returns with it) would otherwise be reported as a
// truncated file. `what` is "PLY" or "OFF". Whole words are looked at, from the word
// `body_after` on (PLY: "end_header", so a comment in the header cannot match) or from the
// second line (OFF: nullptr).
std::string why_text_unreadable(const std::string& path, const std::string& what, const char* body_after) {
  std::ifstream in(path, std::ios::binary);
  in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  std::size_t line = 2;  // the first line was just skipped
  std::string word;
  bool in_body = body_after == nullptr;
  auto non_finite = [](std::string w) {
    if (!w.empty() && (w[0] == '-' || w[0] == '+')) w.erase(0, 1);
    return w == "nan" || w == "inf" || w == "infinity" || w.rfind("nan(", 0) == 0;
  };
  for (char c; in.get(c) || !word.empty();) {
    if (!in || std::isspace(static_cast<unsigned char>(c))) {
      if (!in_body) {
        in_body = word == body_after;
      } else if (non_finite(word)) {
        return "line " + std::to_string(line) + ": a coordinate is NaN or infinite";
      }
      word.clear();
      if (!in) break;
      if (c == '\n') ++line;
      continue;
    }
    if (word.size() < 64) word.push_back(char(std::tolower(static_cast<unsigned char>(c))));  // binary: never a word
  }
  return "unreadable or truncated " + what;
}

// Is `p` a face's vertex index list of 8 or 16 bits (valid PLY, written by some tools to save
// space), which CGAL's PLY reader does not take (int or uint, 32 bits)?
bool is_small_face_index_list(const PlyProperty& p) {
  if (!p.is_list || p.name.rfind("vertex_ind", 0) != 0) return false;
  for (const char* small : {"char", "uchar", "int8", "uint8", "short", "ushort", "int16", "uint16"})
    if (p.index_type == small) return true;
  return false;
}

// Bytes of a PLY scalar type; 0 for a name PLY does not define.
std::size_t ply_type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

// The PLY at `path` (header `h`) with its 8- or 16-bit face indices made 32-bit ("int"), for
// CGAL's reader, which then checks it as any PLY (indices past the vertices, truncation, bytes
// after the elements). assimp reads these files but checks neither: a cut binary file gave
// 161,168 faces on one vertex, and an index past the vertices a face on a vertex of its own.
// Written here because no library at hand converts PLY property types. ASCII bodies are kept
// as they are (only the header's type word changes); binary ones are re-encoded element by
// element in the file's byte order.
std::string with_32_bit_face_indices(const std::string& path, const PlyHeader& h) {
  std::ifstream in(path, std::ios::binary);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string key, list, count_type, index_type, name;
    words >> key >> list >> count_type >> index_type >> name;
    if (key == "property" && list == "list" && is_small_face_index_list({name, count_type, index_type, true}))
      line = "property list " + count_type + " int " + name;
    out += line + "\n";
    if (key == "end_header") break;
  }
  const std::string body((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (h.ascii) return out + body;
  std::size_t at = 0;
  // The next `n` bytes of the body, as an unsigned number in the file's byte order.
  const auto take = [&](std::size_t n, const PlyElement& e, double i) {
    if (at + n > body.size())
      throw bad_input(path, "truncated: its header declares " + format_number(e.count) + " of element " + e.name +
                                ", the file ends in number " + format_number(i + 1) + " (binary)");
    std::uint64_t v = 0;
    for (std::size_t k = 0; k < n; ++k)
      v |= std::uint64_t(static_cast<unsigned char>(body[at + (h.big_endian ? n - 1 - k : k)])) << (8 * k);
    at += n;
    return v;
  };
  const auto put = [&](std::uint64_t v, std::size_t n) {
    for (std::size_t k = 0; k < n; ++k) out.push_back(char(v >> (8 * (h.big_endian ? n - 1 - k : k))));
  };
  for (const PlyElement& e : h.elements)
    for (double i = 0; i < e.count; ++i)
      for (const PlyProperty& p : e.properties) {
        const std::size_t size = ply_type_size(p.type), item = p.is_list ? ply_type_size(p.index_type) : 0;
        if (size == 0 || (p.is_list && item == 0))
          throw bad_input(path, "property " + p.name + " of element " + e.name + " has a type PLY does not define");
        const std::uint64_t v = take(size, e, i);
        put(v, size);
        if (!p.is_list) continue;
        const bool widen = is_small_face_index_list(p), is_signed = p.index_type[0] != 'u';
        for (std::uint64_t k = 0; k < v; ++k) {
          std::uint64_t index = take(item, e, i);
          if (!widen) {
            put(index, item);
            continue;
          }
          if (is_signed && (index >> (8 * item - 1)))  // a negative index stays negative: CGAL names it
            index |= ~std::uint64_t(0) << (8 * item);
          put(index & 0xffffffffu, 4);
        }
      }
  return out + body.substr(at);
}

// A PLY as CGAL's reader takes it: the file itself, or, when its face indices are of 8 or 16
// bits, the file with them made 32-bit (with_32_bit_face_indices). Each open() reads it anew.
class PlyForCgal {
 public:
  PlyForCgal(const std::string& path, const PlyHeader& h) : path_(path) {
    if (!h.complete) return;  // left to CGAL's reader, which names the file unreadable
    for (const PlyElement& e : h.elements)
      if (std::any_of(e.properties.begin(), e.properties.end(), is_small_face_index_list)) {
        widened_ = with_32_bit_face_indices(path, h);
        return;
      }
  }
  std::unique_ptr<std::istream> open() const {
    if (widened_.empty()) return std::make_unique<std::ifstream>(path_, std::ios::binary);
    return std::make_unique<std::istringstream>(widened_, std::ios::binary);
  }

 private:
  std::string path_, widened_;
};

// Why assimp refused an STL, where the bytes can tell: assimp says "Failed to determine STL
// storage representation" both for a cut-off binary STL and for a file that is no STL at all. A
// binary STL is an 80-byte header, a little-endian uint32 triangle count and 50 bytes per
// triangle; an ascii one is text starting with "solid".
std::string why_stl_unreadable(const std::string& path, const std::string& assimp_error) {
  const std::uintmax_t size = fs::file_size(path);
  const std::string head = first_bytes(path, 84);
  const bool text = std::all_of(head.begin(), head.end(), [](char c) {
    return std::isprint(static_cast<unsigned char>(c)) || std::isspace(static_cast<unsigned char>(c));
  });
  if (!text && head.size() == 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, head.data() + 80, 4);  // the file's little-endian is the machine's (x86-64, arm64)
    const std::uintmax_t expected = 84 + 50 * std::uintmax_t(n);
    if (n > 0 && size < expected)
      return "truncated binary STL: its header declares " + std::to_string(n) + " triangles (" +
             std::to_string(expected) + " bytes), the file has " + std::to_string(size) + " bytes";
    // assimp refuses these with the same words as a file that is no STL
    if (size > expected)
      return "binary STL: its header declares " + std::to_string(n) + " triangles (" + std::to_string(expected) +
             " bytes), the file has " + std::to_string(size) +
             " bytes: a count too small, or data appended (two files joined?)";
  }
  if (text && head.rfind("solid", 0) != 0) return "not an STL file: text that does not start with \"solid\"";
  if (!text && size < 84)
    return "not an STL file: " + std::to_string(size) + " bytes, shorter than a binary STL's 84-byte header";
  return "not a readable mesh" + (assimp_error.empty() ? std::string() : ": " + assimp_error);
}

// The numbers of a point line, split at white space, commas or semicolons. A comma is a decimal
// comma where the line's columns are split otherwise: by semicolons ("1,5;2,3;4,1", European
// CSV), or by white space with a comma between two digits ("100,5 0 0"); else it is a separator
// ("1,2,3", "1, 2, 3"). `words` gets the tokens that are not numbers.
std::vector<double> point_line_numbers(std::string line, std::vector<std::string>* words) {
  const bool semicolons = line.find(';') != std::string::npos;
  bool decimal_commas = semicolons;
  if (!semicolons && line.find_first_of(" \t") != std::string::npos)
    for (std::size_t c = line.find(','); c != std::string::npos; c = line.find(',', c + 1))
      decimal_commas = decimal_commas || (c > 0 && c + 1 < line.size() && std::isdigit(static_cast<unsigned char>(line[c - 1])) &&
                                          std::isdigit(static_cast<unsigned char>(line[c + 1])));
  for (char& ch : line)
    if (ch == ';' || (ch == ',' && !decimal_commas)) ch = ' ';
    else if (ch == ',') ch = '.';
  std::istringstream ss(line);
  std::vector<double> v;
  for (std::string tok; ss >> tok;) {
    char* end = nullptr;
    const double x = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0') words->push_back(tok);
    else v.push_back(x);
  }
  return v;
}

// Point lines, one point a line, the same columns on every line: x y z, then anything the
// scanner or tool exports (normals, colours, intensity, a scalar field, in any order: "x y z nx ny
// nz", "x y z r g b", "x y z intensity r g b", CloudCompare's "x y z r g b nx ny nz"), split at
// white space, commas or semicolons (point_line_numbers), after an optional header line of names
// ("X Y Z", "//X,Y,Z") or Leica PTS's count line. The normals are the three columns after x y z
// whose rows are all unit vectors; the other columns are left out, said in `notes`. Written here
// because CGAL's XYZ reader takes "x y z [nx ny nz]" only and silently skips lines it cannot
// parse; a scan with a garbled line is more likely a wrong file, so its line is named.
PointCloud read_xyz(const std::string& path, std::vector<std::string>* notes) {
  std::ifstream in(path);
  std::vector<double> values;  // the rows, `columns` numbers each
  std::size_t columns = 0, rows = 0;
  std::string line;
  std::size_t line_no = 0, columns_line = 0;
  double declared = -1;  // a PTS file's count line
  bool header_seen = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (line_no == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark
    const auto start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#' || line.compare(start, 2, "//") == 0) continue;
    std::vector<std::string> words;
    std::vector<double> v = point_line_numbers(line, &words);
    if (rows == 0 && declared < 0 && !header_seen && v.empty()) {
      header_seen = true;  // "X Y Z R G B": names of the columns
      continue;
    }
    if (!words.empty())
      throw bad_input(path, "line " + std::to_string(line_no) + ": '" + words[0] + "' is not a number");
    if (rows == 0 && declared < 0 && v.size() == 1 && v[0] >= 0 && v[0] == std::floor(v[0])) {
      declared = v[0];  // PTS: the number of points
      continue;
    }
    if (v.size() < 3)
      throw bad_input(path, "line " + std::to_string(line_no) + ": " + std::to_string(v.size()) +
                                " numbers, expected x y z and any further columns");
    if (rows == 0) columns = v.size(), columns_line = line_no;
    if (v.size() != columns)
      throw bad_input(path, "line " + std::to_string(line_no) + " holds " + std::to_string(v.size()) +
                                " numbers, line " + std::to_string(columns_line) + " held " + std::to_string(columns) +
                                ": one kind of line a file");
    values.insert(values.end(), v.begin(), v.end());
    ++rows;
  }
  if (declared >= 0 && double(rows) != declared)
    throw bad_input(path, "its first line declares " + format_number(declared) + " points, the file holds " +
                              std::to_string(rows) + " (truncated or edited?)");
  PointCloud c;
  const auto row = [&](std::size_t i) { return &values[i * columns]; };
  for (std::size_t i = 0; i < rows; ++i) c.points.emplace_back(row(i)[0], row(i)[1], row(i)[2]);
  // The normals: the first three consecutive columns after x y z that are unit vectors on every
  // row (|n| within 0.05 of 1). Colours (255 0 0, or 0-1 floats) and intensities are not, and
  // colours read as normals had steered the orientation and Poisson.
  std::size_t normals_at = 0;
  for (std::size_t k = 3; k + 3 <= columns && normals_at == 0; ++k) {
    bool unit = true;
    for (std::size_t i = 0; i < rows && unit; ++i) {
      const double* r = row(i);
      unit = std::fabs(std::sqrt(r[k] * r[k] + r[k + 1] * r[k + 1] + r[k + 2] * r[k + 2]) - 1) < 0.05;
    }
    if (unit) normals_at = k;
  }
  if (normals_at > 0)
    for (std::size_t i = 0; i < rows; ++i) c.normals.emplace_back(row(i)[normals_at], row(i)[normals_at + 1], row(i)[normals_at + 2]);
  // The columns left out, counted from 1 as a spreadsheet shows them: "column 7", "columns 4-7".
  std::vector<std::pair<std::size_t, std::size_t>> left;  // ranges, 1-based
  for (std::size_t k = 3; k < columns; ++k) {
    if (normals_at > 0 && k >= normals_at && k < normals_at + 3) continue;
    if (!left.empty() && left.back().second == k) left.back().second = k + 1;
    else left.push_back({k + 1, k + 1});
  }
  if (!left.empty()) {
    std::string ranges;
    for (const auto& [from, to] : left)
      ranges += (ranges.empty() ? "" : " and ") + std::to_string(from) + (to > from ? "-" + std::to_string(to) : "");
    const bool one = left.size() == 1 && left[0].first == left[0].second;
    notes->push_back((one ? "column " : "columns ") + ranges + " left out (colours, intensity or other values" +
                     (normals_at > 0 ? "; the normals are columns " + std::to_string(normals_at + 1) + "-" +
                                           std::to_string(normals_at + 3) + ")"
                                     : "; no three columns are unit normals, so the normals are estimated)"));
  }
  return c;
}

// Runs one of CGAL's PLY reads. It sizes a face's index list from the file, so a damaged count
// (0x7fffffff, or -3 read as unsigned) ended the stage as "internal error: std::bad_alloc" or
// "vector::_M_default_append", naming no file.
template <class Read>
bool read_ply_guarded(const std::string& path, Read&& read) {
  try {
    return read();
  } catch (const std::bad_alloc&) {
  } catch (const std::length_error&) {
  }
  throw bad_input(path, "damaged PLY: it declares a list or element larger than memory can hold");
}

// What follows the last element a PLY's header declares. CGAL stops reading there, so a header
// whose count was lowered (an edited file, a writer that counted wrong) lost the rest silently: a
// 1,000-point scan declared as 500 was read as 500 points. Trailing white space (a final newline
// after binary data) is harmless and allowed.
void require_nothing_after_elements(std::istream& in, const std::string& path) {
  if (in.bad()) return;
  in.clear();
  std::size_t extra = 0;
  bool blank = true;
  for (int c = in.get(); c != std::char_traits<char>::eof(); c = in.get()) {
    ++extra;
    blank = blank && std::isspace(c);
  }
  if (!blank)
    throw bad_input(path, std::to_string(extra) + " bytes after the elements its header declares: "
                          "a count in the header is too small, or data was appended (damaged or hand-edited file?)");
}

// The header of the PLY at `path`, once its magic and (ASCII) its lines are checked.
PlyHeader read_checked_ply_header(const std::string& path) {
  if (first_bytes(path, 3) != "ply") throw bad_input(path, "not a PLY file (no 'ply' magic)");
  std::ifstream in(path, std::ios::binary);
  const PlyHeader header = read_ply_header(in);
  require_ascii_ply_lines_match_header(path, in, header);
  return header;
}

// `ply` (the file at `path`) read by CGAL as a polygon soup, with nothing after its elements.
void read_ply_soup(const std::string& path, const PlyForCgal& ply, std::vector<Point>& points,
                   std::vector<std::vector<std::size_t>>& polygons) {
  const auto in = ply.open();
  if (!read_ply_guarded(path, [&] { return CGAL::IO::read_PLY(*in, points, polygons); }))
    throw bad_input(path, why_text_unreadable(path, "PLY", "end_header"));
  require_nothing_after_elements(*in, path);
}

// The names of the normal's three properties of a PLY's vertices: "nx ny nz" (CGAL, MeshLab,
// CloudCompare) or "normal_x normal_y normal_z" (PCL), which CGAL's point reader does not look
// for (such normals were ignored and estimated again). Empty when the vertices have neither.
std::array<std::string, 3> ply_normal_names(const PlyHeader& header) {
  for (const auto& e : header.elements) {
    if (e.name != "vertex") continue;
    const auto has = [&](const char* name) {
      return std::any_of(e.properties.begin(), e.properties.end(), [&](const PlyProperty& p) { return p.name == name; });
    };
    if (has("nx") && has("ny") && has("nz")) return {"nx", "ny", "nz"};
    if (has("normal_x") && has("normal_y") && has("normal_z")) return {"normal_x", "normal_y", "normal_z"};
  }
  return {};
}

void read_ply(const std::string& path, Scan& scan) {
  const PlyHeader header = read_checked_ply_header(path);
  const PlyForCgal ply(path, header);
  std::vector<Point> pts;
  std::vector<std::vector<std::size_t>> polys;
  read_ply_soup(path, ply, pts, polys);
  if (!polys.empty()) {
    scan.is_mesh = true;
    scan.soup.points = std::move(pts);
    scan.soup.polygons = std::move(polys);
    return;
  }
  // A point set: the soup read gave its points; read again for the normals, if it has any.
  const auto normal = ply_normal_names(header);
  if (normal[0].empty()) {
    scan.cloud.points = std::move(pts);
    return;
  }
  using PN = std::pair<Point, Vector>;
  std::vector<PN> pn;
  const auto in2 = ply.open();
  using Property = CGAL::IO::PLY_property<double>;
  if (!read_ply_guarded(path, [&] {
        return CGAL::IO::read_PLY_with_properties(
            *in2, std::back_inserter(pn), CGAL::IO::make_ply_point_reader(CGAL::First_of_pair_property_map<PN>()),
            std::make_tuple(CGAL::Second_of_pair_property_map<PN>(), Kernel::Construct_vector_3(),
                            Property(normal[0].c_str()), Property(normal[1].c_str()), Property(normal[2].c_str())));
      }))
    throw bad_input(path, why_text_unreadable(path, "PLY point set", "end_header"));
  bool has_normals = false;
  for (const auto& p : pn) has_normals |= p.second.squared_length() > 0;
  for (const auto& p : pn) {
    scan.cloud.points.push_back(p.first);
    if (has_normals) scan.cloud.normals.push_back(p.second);
  }
}

// An OFF header's vertex and face counts against the file's size: CGAL reserves what the header
// declares, so a damaged count (2,000,000,000 vertices in a 60-byte file) ended the stage as
// "internal error: std::bad_alloc", naming no file. ASCII needs at least 6 bytes a vertex
// ("0 0 0\n") and 8 a triangle ("3 0 1 2\n"); binary OFF more. Counts it cannot parse are left
// to CGAL's reader.
void check_off_counts(const std::string& path) {
  std::ifstream in(path);
  std::string word;
  std::vector<double> counts;
  while (counts.size() < 2 && in >> word) {
    if (word[0] == '#') {
      std::getline(in, word);
      continue;
    }
    if (word.find("OFF") != std::string::npos) continue;
    char* end = nullptr;
    const double v = std::strtod(word.c_str(), &end);
    if (*end != '\0') return;
    counts.push_back(v);
  }
  if (counts.size() < 2) return;
  std::error_code ec;
  const double bytes = double(std::filesystem::file_size(path, ec));
  if (!ec && 6 * counts[0] + 8 * counts[1] > bytes)
    throw bad_input(path, "the OFF header declares " + format_number(counts[0]) + " vertices and " +
                              format_number(counts[1]) + " faces, more than its " + format_number(bytes) +
                              " bytes can hold: truncated or damaged");
}

// The first word of an OFF file that is not a comment: its keyword ("OFF", "NOFF", "COFF", ...).
std::string off_keyword(const std::string& path) {
  std::ifstream in(path);
  std::string word;
  while (in >> word && word[0] == '#') std::getline(in, word);
  return word;
}

// The normals of an NOFF point set ("x y z nx ny nz" on each vertex line), which the soup reader
// skips: they were estimated again. CGAL's point-set OFF reader takes them, but only from a file
// laid out one vertex a line; when it cannot, the points stay without normals and a note says so.
void read_noff_normals(const std::string& path, Scan& scan) {
  using PN = std::pair<Point, Vector>;
  std::vector<PN> pn;
  std::ifstream in(path);
  // CGAL writes why it stops to std::cerr ("Error line 2 of file (incorrect header format)"):
  // kept quiet, the note below says it
  struct QuietCerr {
    std::ostringstream sink;
    std::streambuf* const kept = std::cerr.rdbuf(sink.rdbuf());
    ~QuietCerr() { std::cerr.rdbuf(kept); }
  };
  bool read = false;
  {
    const QuietCerr quiet;
    read = CGAL::IO::read_OFF(in, std::back_inserter(pn),
                              CGAL::parameters::point_map(CGAL::First_of_pair_property_map<PN>())
                                  .normal_map(CGAL::Second_of_pair_property_map<PN>()));
  }
  if (!read || pn.size() != scan.cloud.points.size()) {
    scan.notes.push_back("its NOFF normals were not read (not one vertex a line), so they are estimated");
    return;
  }
  for (const auto& p : pn) scan.cloud.normals.push_back(p.second);
}

void read_off(const std::string& path, Scan& scan) {
  const std::string head = first_bytes(path, 4);
  if (head.find("OFF") == std::string::npos) throw bad_input(path, "not an OFF file (no 'OFF' header)");
  check_off_counts(path);
  std::vector<Point> pts;
  std::vector<std::vector<std::size_t>> polys;
  std::ifstream in(path);
  if (!CGAL::IO::read_OFF(in, pts, polys)) throw bad_input(path, why_text_unreadable(path, "OFF", nullptr));
  // as in a PLY: a face count lowered to 10,000 of 20,146 lost half the head, and repair made a
  // 100 mm blob of the rest with exit 0
  require_nothing_after_elements(in, path);
  if (polys.empty()) {
    scan.cloud.points = std::move(pts);
    if (off_keyword(path) == "NOFF") read_noff_normals(path, scan);
  } else {
    scan.is_mesh = true;
    scan.soup.points = std::move(pts);
    scan.soup.polygons = std::move(polys);
  }
}

// The keyword of an OBJ line ("v", "vn", "f", ...), after any leading white space: a face line
// indented or written "f\t1\t2\t3" was not seen, and the mesh was read as a cloud of its vertices.
std::string obj_keyword(const std::string& line) {
  std::istringstream words(line);
  std::string keyword;
  words >> keyword;
  return keyword;
}

// The vertices of an OBJ without faces (`text`, the file at `path`), with their normals when the
// file gives one "vn" a "v" (as point-cloud exporters write them, in the same order).
PointCloud read_obj_points(const std::string& path, const std::string& text) {
  std::istringstream in(text);
  PointCloud c;
  std::string line;
  while (std::getline(in, line)) {
    const std::string keyword = obj_keyword(line);
    if (keyword != "v" && keyword != "vn") continue;
    std::istringstream ss(line.substr(line.find(keyword) + keyword.size()));
    double x, y, z;
    if (!(ss >> x >> y >> z)) throw bad_input(path, "malformed " + keyword + " line '" + line + "'");
    if (keyword == "v")
      c.points.emplace_back(x, y, z);
    else
      c.normals.emplace_back(x, y, z);
  }
  if (c.normals.size() != c.points.size()) c.normals.clear();
  return c;
}

// What an OBJ's text says about how to read it: whether it has faces (OBJ files with vertices
// only are point clouds, which assimp does not import), and whether any line is indented or holds
// a tab, which assimp's OBJ parser mishandles: it skipped an indented face line or one written
// "f\t1\t2\t3" (a mesh read with 2 of its 4 faces), and refused indented vertex lines ("vertex
// index out of range").
struct ObjLayout {
  bool has_faces = false, indented_or_tabbed = false;
};
ObjLayout obj_layout(const std::string& text) {
  ObjLayout layout;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    layout.has_faces = layout.has_faces || obj_keyword(line) == "f";
    const std::size_t start = line.find_first_not_of(" \t");
    layout.indented_or_tabbed = layout.indented_or_tabbed || (start != 0 && start != std::string::npos) ||
                                line.find('\t') != std::string::npos;
  }
  return layout;
}

// An OBJ's text with each line's leading white space removed and tabs made spaces, for assimp.
std::string obj_text_assimp_reads(const std::string& text) {
  std::istringstream in(text);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    line.erase(0, std::min(line.find_first_not_of(" \t"), line.size()));
    std::replace(line.begin(), line.end(), '\t', ' ');
    out += line + "\n";
  }
  return out;
}

// An ASCII STL written in upper case ("SOLID", "FACET NORMAL"), lower-cased for assimp, which
// refused it ("text that does not start with \"solid\""); "" for any other file.
std::string upper_case_stl_text(const std::string& path) {
  const std::string head = first_bytes(path, 5);
  std::string lower = head;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  if (lower != "solid" || head == "solid") return "";
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char ch : text)
    if (!std::isprint(static_cast<unsigned char>(ch)) && !std::isspace(static_cast<unsigned char>(ch))) return "";
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  return text;
}

// The mesh at `path` (STL or OBJ) read by assimp, from the file or, when `text` is not empty, from
// that text: the file's own, rewritten where assimp would misread it.
void read_with_assimp(const std::string& path, Scan& scan, const std::string& text) {
  Assimp::Importer importer;
  // Keep the triangles as scanned: only join the duplicated corners STL stores per facet.
  // Facet normals would keep corners apart, so they are dropped before the join.
  const unsigned steps = aiProcess_DropNormals | aiProcess_JoinIdenticalVertices | aiProcess_Triangulate;
  const std::string ext = lower_extension(path);
  const aiScene* sc = text.empty() ? importer.ReadFile(path, steps)
                                   : importer.ReadFileFromMemory(text.data(), text.size(), steps, ext.substr(1).c_str());
  if (!sc || !sc->mNumMeshes) {
    const std::string why = importer.GetErrorString();
    if (ext == ".stl") throw bad_input(path, why_stl_unreadable(path, why));
    throw bad_input(path, "not a readable mesh" + (why.empty() ? std::string() : ": " + why));
  }
  scan.is_mesh = true;
  for (unsigned m = 0; m < sc->mNumMeshes; ++m) {
    const aiMesh* mesh = sc->mMeshes[m];
    const std::size_t base = scan.soup.points.size();
    for (unsigned v = 0; v < mesh->mNumVertices; ++v)
      scan.soup.points.emplace_back(mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z);
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices < 3) continue;  // points and lines are not surface
      std::vector<std::size_t> poly;
      for (unsigned k = 0; k < face.mNumIndices; ++k) poly.push_back(base + face.mIndices[k]);
      scan.soup.polygons.push_back(std::move(poly));
    }
  }
  if (scan.soup.polygons.empty()) throw bad_input(path, "mesh has no faces");
}

// An OBJ, read into memory once: a point cloud when it has no faces, else a mesh through assimp.
void read_obj(const std::string& path, Scan& scan) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const ObjLayout layout = obj_layout(text);
  if (!layout.has_faces)
    scan.cloud = read_obj_points(path, text);
  else
    read_with_assimp(path, scan, layout.indented_or_tabbed ? obj_text_assimp_reads(text) : "");
}

void scale_points(std::vector<Point>& pts, double s) {
  if (s == 1.0) return;
  for (auto& p : pts) p = Point(p.x() * s, p.y() * s, p.z() * s);
}

}  // namespace

Scan read_scan(const std::string& path, const ScanReadOptions& opt) {
  require_file(path);
  const std::string ext = lower_extension(path);
  Scan scan;
  if (ext == ".xyz" || ext == ".pts" || ext == ".txt" || ext == ".csv" || ext == ".asc")
    scan.cloud = read_xyz(path, &scan.notes);
  else if (ext == ".ply") read_ply(path, scan);
  else if (ext == ".off") read_off(path, scan);
  else if (ext == ".obj") read_obj(path, scan);
  else if (ext == ".stl") read_with_assimp(path, scan, upper_case_stl_text(path));
  else throw bad_input(path, "unknown scan format '" + ext + "', expected .ply .stl .obj .off, or points as text: .xyz .pts .txt .csv .asc");

  auto& pts = scan.is_mesh ? scan.soup.points : scan.cloud.points;
  if (pts.empty()) throw bad_input(path, "no points in file");
  check_finite(pts, path, "vertex", "coordinate");
  check_finite(scan.cloud.normals, path, "point", "normal");
  check_face_indices(scan.soup.polygons, pts.size(), path);
  // Vertices no face uses carry no surface but counted in the size that decides the unit: a stray
  // point (a scanner's marker at the origin) made a head look metres wide.
  if (scan.is_mesh) PMP::remove_isolated_points_in_polygon_soup(scan.soup.points, scan.soup.polygons);

  const double extent = extent_without_far_points(pts);  // in the file's unit
  scan.unit = opt.unit == Unit::automatic ? detect_unit(extent, opt.expected_size_mm, path) : opt.unit;
  scale_points(pts, mm_per_unit(scan.unit));
  scan.extent_mm = extent * mm_per_unit(scan.unit);
  return scan;
}

SurfaceMesh read_surface_mesh(const std::string& path) {
  require_file(path);
  SurfaceMesh mesh;
  const std::string ext = lower_extension(path);
  if (ext == ".ply") {
    const PlyHeader header = read_checked_ply_header(path);
    // A valid PLY may list its faces before its vertices; CGAL's Surface_mesh reader then
    // crashed (it indexes vertices it has not read yet).
    bool vertices_seen = false;
    for (const PlyElement& e : header.elements) {
      vertices_seen = vertices_seen || e.name == "vertex";
      if (e.name == "face" && !vertices_seen)
        throw bad_input(path, "its faces come before its vertices: a mesh a stage wrote lists vertices first");
    }
    const PlyForCgal ply(path, header);
    // Read as a soup first: CGAL's PLY-to-Surface_mesh reader fails alike on a broken file and
    // on a valid one whose faces do not form a 2-manifold, and it crashes on a face index past
    // the vertices (a corrupted binary file); the soup tells the three apart safely. The mesh is
    // then read by CGAL's mesh reader, not built from the soup: it keeps the face properties
    // (segment's part labels) that the later stages read.
    {
      std::vector<Point> points;
      std::vector<std::vector<std::size_t>> polygons;
      read_ply_soup(path, ply, points, polygons);
      check_face_indices(polygons, points.size(), path);
      if (!polygons.empty() && !PMP::is_polygon_soup_a_polygon_mesh(polygons))
        throw bad_input(path, "not a 2-manifold polygon mesh (" + std::to_string(polygons.size()) +
                                  " faces read; run repair first)");
    }
    const auto in = ply.open();
    std::string comments;
    if (!read_ply_guarded(path, [&] { return CGAL::IO::read_PLY(*in, mesh, comments); }))
      throw bad_input(path, "unreadable or truncated PLY");
  } else {
    Scan scan = read_scan(path, ScanReadOptions{Unit::mm});
    if (!scan.is_mesh) throw bad_input(path, "is a point set, expected a mesh");
    if (!PMP::is_polygon_soup_a_polygon_mesh(scan.soup.polygons))
      throw bad_input(path, "not a 2-manifold polygon mesh (run repair first)");
    PMP::polygon_soup_to_polygon_mesh(scan.soup.points, scan.soup.polygons, mesh);
  }
  if (mesh.number_of_faces() == 0) throw bad_input(path, "mesh has no faces");
  // Every stage writes triangles, and every reader of this mesh (AABB trees, samplers, ray
  // grids) takes three corners of a face: of a square it saw half (sweep S).
  for (auto f : mesh.faces())
    if (mesh.degree(f) != 3)
      throw bad_input(path, "face " + std::to_string(std::size_t(f)) + " has " + std::to_string(mesh.degree(f)) +
                                " corners, expected triangles (a stage's output; run repair first)");
  for (auto v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
      throw bad_input(path, "vertex " + std::to_string(std::size_t(v)) + " has a non-finite coordinate");
  }
  // as in read_scan: vertices no face uses counted in the size checks (no stage writes any);
  // removed after the check above, whose vertex numbers are the file's
  for (auto v : mesh.vertices())
    if (mesh.is_isolated(v)) mesh.remove_vertex(v);
  if (mesh.has_garbage()) mesh.collect_garbage();
  // A stage's output has none (repair removes them); in an edited or corrupted file they made
  // CGAL's remeshing (surface_mesh) crash and segment's ray tests assert or cut absurd parts.
  std::size_t degenerate = 0, first = 0;
  for (auto f : mesh.faces())
    if (PMP::is_degenerate_triangle_face(f, mesh) && degenerate++ == 0) first = std::size_t(f);
  if (degenerate > 0)
    throw bad_input(path, std::to_string(degenerate) + " degenerate face" + (degenerate > 1 ? "s" : "") +
                              " (zero area; the first is face " + std::to_string(first) + "): run repair first");
  return mesh;
}

}  // namespace pipeline
