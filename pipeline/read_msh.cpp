// read_msh: see read_msh.h.
#include "pipeline/read_msh.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string_view>
#include <vector>

#include "pipeline/error.h"
#include "pipeline/gmsh_session.h"
#include "pipeline/require_file.h"

namespace pipeline {
namespace {

MshFile read_open_model(const std::string& path) {
  MshFile f;
  std::vector<std::size_t> tags;
  std::vector<double> xyz, param;
  gmsh::model::mesh::getNodes(tags, xyz, param, -1, -1, false, false);
  if (tags.empty()) throw bad_input(path, "no nodes (empty, or not a gmsh mesh)");
  // Tag → where gmsh lists it first (a node on an entity's boundary may be listed once per
  // entity), then → its index in f once it is stored there.
  std::map<std::size_t, std::size_t> index;
  for (std::size_t i = 0; i < tags.size(); ++i) {
    const auto [it, first] = index.emplace(tags[i], i);
    // Listed again at other coordinates: a tag defined twice (a mesh merged by hand), of which
    // the first coordinates had won without a word.
    if (!first)
      for (int k = 0; k < 3; ++k)
        if (xyz[3 * i + k] != xyz[3 * it->second + k])
          throw bad_input(path, "node " + std::to_string(tags[i]) + " is defined twice, at different coordinates");
  }
  // The nodes in tag order, not gmsh's: gmsh lists them entity by entity, and createTopology
  // numbers the curve and point entities of surface_mesh's output in pointer order, so the same
  // surface read from another path listed its nodes in another order and layers wrote a
  // permuted model. Tags are the writer's and do not move.
  for (auto& [tag, i] : index) {
    // Checked here because a NaN node slips through every later geometric test (comparisons
    // with NaN are false) and surfaces as thinning failures or a floating-point trap.
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(xyz[3 * i + k]))
        throw bad_input(path, "node " + std::to_string(tag) + " has a non-finite coordinate");
    f.xyz.insert(f.xyz.end(), xyz.begin() + 3 * long(i), xyz.begin() + 3 * long(i) + 3);
    i = f.node_tags.size();
    f.node_tags.push_back(tag);
  }
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups);
  for (const auto& [dim, tag] : groups) {
    MshGroup g;
    g.dim = dim;
    g.tag = tag;
    gmsh::model::getPhysicalName(dim, tag, g.name);
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
    for (int entity : entities) {
      std::vector<int> types;
      std::vector<std::vector<std::size_t>> element_tags, element_nodes;
      gmsh::model::mesh::getElements(types, element_tags, element_nodes, dim, entity);
      for (std::size_t t = 0; t < types.size(); ++t) {
        MshElements block;
        block.gmsh_type = types[t];
        std::string type_name;
        int type_dim, order, primary_nodes;
        std::vector<double> local_coords;
        gmsh::model::mesh::getElementProperties(types[t], type_name, type_dim, order, block.nodes_per_element,
                                                local_coords, primary_nodes);
        block.conn.reserve(element_nodes[t].size());
        for (std::size_t n : element_nodes[t]) {
          const auto it = index.find(n);
          if (it == index.end())
            throw bad_input(path, "an element of group " + (g.name.empty() ? std::to_string(tag) : g.name) +
                                      " uses missing node " + std::to_string(n));
          block.conn.push_back(int(it->second));
        }
        g.elements.push_back(std::move(block));
      }
    }
    f.groups.push_back(std::move(g));
  }
  return f;
}

// What gmsh is given is checked first, because gmsh trusts it: a file that does not start with
// $MeshFormat it runs as a .geo script (a "System" line ran a shell command, and a plain text file
// gave "Unknown variable"); in an ASCII mesh it believes the counts (a block declaring 4e9
// elements aborted libgmsh 4.8 with a double free) and the node tags (-3 crashed getElements);
// and a $Nodes section that lost its $EndNodes it reads without a word, skipping to the end of
// the file, so the elements vanished and a stage wrote an empty model with exit 0. gmsh has no
// option to read a mesh only, so an ASCII file's sections, block counts and element node tags are
// checked here. A binary file's sections hold raw bytes after $MeshFormat and are left to gmsh.
class MshText {
 public:
  explicit MshText(const std::string& path) : path_(path) {
    std::ifstream in(path, std::ios::binary);
    // A binary file's sections are raw bytes: only its head is read, up to the format line.
    for (std::string line; std::getline(in, line) && text_.size() < 100000;) {
      text_ += line + "\n";
      if (line.rfind("$MeshFormat", 0) == 0 && std::getline(in, line)) {
        text_ += line + "\n";
        std::istringstream format(line);
        std::string file_type;
        format >> format_version_ >> file_type;
        binary_ = file_type == "1";
        break;
      }
    }
    if (!binary_) {
      std::ostringstream rest;
      rest << in.rdbuf();
      text_ += rest.str();
    }
    for (std::size_t start = 0; start < text_.size();) {
      std::size_t end = text_.find('\n', start);
      if (end == std::string::npos) end = text_.size();
      std::size_t last = end;  // without "\r" and trailing blanks, as gmsh reads the line
      while (last > start && (text_[last - 1] == '\r' || text_[last - 1] == ' ' || text_[last - 1] == '\t')) --last;
      lines_.emplace_back(text_.data() + start, last - start);
      start = end + 1;
    }
  }

  void check() const {
    if (lines_.empty() || (lines_[0] != "$MeshFormat" && lines_[0] != "$Comments"))
      throw bad_input(path_, "not a gmsh mesh: its first line is '" + shown(lines_.empty() ? "" : lines_[0]) +
                                 "', expected $MeshFormat");
    if (binary_) return;
    const std::string& version = format_version_;
    for (const Section& s : sections()) {
      if (s.name == "Nodes" && version == "4.1") check_nodes_41(s);
      if (s.name == "Elements" && version == "4.1") check_elements_41(s);
      if (s.name == "Nodes" && version.rfind("2.", 0) == 0) check_count_22(s, "nodes");
      if (s.name == "Elements" && version.rfind("2.", 0) == 0) check_elements_22(s);
      if (s.name == "PhysicalNames") check_physical_names(s);
    }
  }

 private:
  struct Section {
    std::string name;
    std::size_t begin, end;  ///< line indices of $name and $Endname
  };

  std::vector<Section> sections() const {
    std::vector<Section> out;
    bool open = false;
    const auto not_closed = [&](const std::string& where) {
      return bad_input(path_, "section $" + out.back().name + " (line " + std::to_string(out.back().begin + 1) +
                                  ") is not closed by $End" + out.back().name + " " + where);
    };
    for (std::size_t i = 0; i < lines_.size(); ++i) {
      const std::string_view line = lines_[i];
      if (line.empty() || line[0] != '$') continue;
      const std::string name(line.substr(1));
      if (!open) {
        if (name.rfind("End", 0) == 0) throw error(i, std::string(line) + " closes no open section");
        out.push_back({name, i, 0});
        open = true;
      } else if (name == "End" + out.back().name) {
        out.back().end = i;
        open = false;
      } else if (out.back().name != "Comments") {
        throw not_closed("before line " + std::to_string(i + 1) + " (" + std::string(line) + ")");
      }
    }
    if (open) throw not_closed("(truncated file?)");
    return out;
  }

  // 4.1: "blocks nodes min max", then per block "dim tag parametric n", n tag lines, n coordinate lines.
  void check_nodes_41(const Section& s) const {
    std::size_t i = s.begin + 1;
    const long long blocks = count(i, 0, "'<blocks> <nodes> <min tag> <max tag>'");
    for (long long b = 0; b < blocks; ++b) {
      const long long n = count(++i, 3, "'<dim> <entity> <parametric> <nodes in block>'");
      if (n > (long long)(s.end - i - 1) / 2) throw too_many(i, n, "nodes", s.end - i - 1);
      i += 2 * std::size_t(n);
    }
    if (i + 1 != s.end) throw error(i + 1, "more lines in $Nodes than its blocks declare");
  }

  // 4.1: "blocks elements min max", then per block "dim tag type n" and n lines "tag node...".
  void check_elements_41(const Section& s) const {
    std::size_t i = s.begin + 1;
    const long long blocks = count(i, 0, "'<blocks> <elements> <min tag> <max tag>'");
    for (long long b = 0; b < blocks; ++b) {
      const long long n = count(++i, 3, "'<dim> <entity> <type> <elements in block>'");
      if (n > (long long)(s.end - i - 1)) throw too_many(i, n, "elements", s.end - i - 1);
      for (long long e = 0; e < n; ++e) check_tags(++i, 1);
    }
    if (i + 1 != s.end) throw error(i + 1, "more lines in $Elements than its blocks declare");
  }

  // "n", then n lines '<dim> <tag> "<name>"' (2.x and 4.x). gmsh keeps one name per group, so a
  // group named twice lost one name silently (the respirator's rim group read as its inner face).
  void check_physical_names(const Section& s) const {
    check_count_22(s, "physical names");
    std::map<std::pair<long long, long long>, std::string> name_of;  // (dim, tag) → name
    std::map<std::pair<long long, std::string>, long long> tag_of;     // (dim, name) → tag
    for (std::size_t i = s.begin + 2; i < s.end; ++i) {
      const auto w = words(lines_[i]);
      if (w.size() < 3) throw error(i, "expected '<dim> <tag> \"<name>\"', got '" + shown(lines_[i]) + "'");
      const long long dim = integer(w[0], i), tag = integer(w[1], i);
      const std::string name(lines_[i].substr(std::size_t(w[2].data() - lines_[i].data())));
      if (const auto [it, added] = name_of.emplace(std::make_pair(dim, tag), name); !added)
        throw error(i, "physical group " + std::to_string(tag) + " of dimension " + std::to_string(dim) +
                           " is named twice, " + it->second + " and " + name);
      if (const auto [it, added] = tag_of.emplace(std::make_pair(dim, name), tag); !added)
        throw error(i, "two physical groups of dimension " + std::to_string(dim) + " are named " + name + " (tags " +
                           std::to_string(it->second) + " and " + std::to_string(tag) + ")");
    }
  }

  // 2.x: "n", then n lines.
  void check_count_22(const Section& s, const char* what) const {
    const long long n = count(s.begin + 1, 0, std::string("the number of ") + what);
    if (n != (long long)(s.end - s.begin - 2))
      throw error(s.begin + 1, "$" + s.name + " declares " + std::to_string(n) + " " + what + " but holds " +
                                   std::to_string(s.end - s.begin - 2) + " lines");
  }

  // 2.x: "n", then n lines "tag type ntags tag... node...".
  void check_elements_22(const Section& s) const {
    check_count_22(s, "elements");
    for (std::size_t i = s.begin + 2; i < s.end; ++i) {
      const auto w = words(lines_[i]);
      const long long ntags = w.size() >= 3 ? integer(w[2], i) : -1;
      if (ntags < 0 || (long long)w.size() < 4 + ntags) throw error(i, "expected '<tag> <type> <ntags> <tags...> <nodes...>'");
      check_tags(i, 3 + std::size_t(ntags));  // a point element (type 15) has one node
    }
  }

  // The element tag (word 0) and node tags (words from `first_node` on) of line i, each a
  // positive integer; at least one node.
  void check_tags(std::size_t i, std::size_t first_node) const {
    const auto w = words(lines_[i]);
    if (w.size() <= first_node) throw error(i, "expected an element tag and its node tags, got '" + shown(lines_[i]) + "'");
    for (std::size_t k = 0; k < w.size(); k = k == 0 ? first_node : k + 1)
      if (integer(w[k], i) < 1) throw error(i, "tag '" + std::string(w[k]) + "' is not a positive integer");
  }

  // Word k of line i as a count >= 0.
  long long count(std::size_t i, std::size_t k, const std::string& expected) const {
    if (i >= lines_.size()) throw error(i, "the file ends where " + expected + " was expected");
    const auto w = words(lines_[i]);
    if (w.size() <= k) throw error(i, "expected " + expected + ", got '" + shown(lines_[i]) + "'");
    const long long n = integer(w[k], i);
    if (n < 0) throw error(i, "negative count " + std::string(w[k]));
    return n;
  }

  long long integer(std::string_view word, std::size_t i) const {
    long long v = 0;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
    if (ec != std::errc() || end != word.data() + word.size())
      throw error(i, "'" + shown(word) + "' is not an integer");
    return v;
  }

  static std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> out;
    for (std::size_t a = 0; a < line.size();) {
      a = line.find_first_not_of(" \t", a);
      if (a == std::string_view::npos) break;
      const std::size_t b = std::min(line.find_first_of(" \t", a), line.size());
      out.push_back(line.substr(a, b - a));
      a = b;
    }
    return out;
  }

  static std::string shown(std::string_view s) { return s.size() > 40 ? std::string(s.substr(0, 40)) + "..." : std::string(s); }

  Error error(std::size_t i, const std::string& problem) const {
    return bad_input(path_, "line " + std::to_string(i + 1) + ": " + problem);
  }
  Error too_many(std::size_t i, long long n, const char* what, std::size_t left) const {
    return error(i, "a block of " + std::to_string(n) + " " + what + ", but its section has " + std::to_string(left) +
                        (left == 1 ? " line" : " lines") + " left (truncated or corrupt file?)");
  }

  std::string path_, text_, format_version_;
  bool binary_ = false;
  std::vector<std::string_view> lines_;
};

}  // namespace

MshFile read_msh(const std::string& path) {
  require_file(path);
  GmshSession session;
  try {
    MshText(path).check();
    gmsh::open(path);
    return read_open_model(path);
  } catch (const std::string& e) {  // the gmsh API throws its last error message as a string
    throw bad_input(path, "gmsh cannot read it: " + e);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw bad_input(path, std::string("gmsh cannot read it: ") + e.what());
  }
}

}  // namespace pipeline
