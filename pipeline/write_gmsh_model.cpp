#include "pipeline/write_gmsh_model.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <gmsh.h>

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"

namespace pipeline {

void require_complete_msh(const std::string& file, const std::string& name) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw io_failed(name, "cannot read back what was written");
  std::string line, open;
  bool nodes = false, elements = false, ends_with_section_end = false;
  while (std::getline(in, line)) {
    ends_with_section_end = false;
    if (line.empty() || line[0] != '$') continue;  // data lines never start with '$'
    if (line.back() == '\r') line.pop_back();
    if (open.empty()) {
      open = line.substr(1);
    } else if (line == "$End" + open) {
      nodes = nodes || open == "Nodes";
      elements = elements || open == "Elements";
      open.clear();
      ends_with_section_end = !in.eof();  // getline stopped at a newline, not at the end of the file
    } else {
      break;  // a section opened inside another: the file is damaged
    }
  }
  if (open.empty() && nodes && elements && ends_with_section_end && in.peek() == EOF) return;
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(file, ec);
  throw io_failed(name, "written incompletely (" + std::to_string(ec ? 0 : bytes) + " bytes, " +
                            (!open.empty() ? "cut inside $" + open
                             : !nodes      ? std::string("no $Nodes")
                             : !elements   ? std::string("no $Elements")
                                           : std::string("no end line")) +
                            "): disk full or a file size limit?");
}

void write_gmsh_model(const std::string& path, const std::function<void(const std::string&)>& append) {
  write_atomic(path, [&](const std::string& tmp) {
    // gmsh would report a folder it cannot write in with the temporary name and no reason.
    if (std::FILE* probe = std::fopen(tmp.c_str(), "w")) {
      std::fclose(probe);
    } else {
      const std::filesystem::path dir = std::filesystem::path(path).parent_path();
      throw io_failed(path, "cannot write in " + (dir.empty() ? std::string(".") : dir.string()) + ": " +
                                std::strerror(errno));
    }
    gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
    gmsh::option::setNumber("Mesh.Binary", 0);
    gmsh::option::setNumber("Mesh.SaveAll", 0);
    try {
      gmsh::write(tmp);
    } catch (const std::string& e) {
      throw io_failed(path, "gmsh cannot write the mesh: " + e);
    }
    if (append) append(tmp);
    require_complete_msh(tmp, path);
  });
}

}  // namespace pipeline
