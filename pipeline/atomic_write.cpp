#include "pipeline/atomic_write.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "pipeline/error.h"
#include "pipeline/require_file.h"

namespace fs = std::filesystem;

namespace pipeline {

void write_atomic(const std::string& path, const std::function<void(const std::string&)>& writer) {
  const fs::path target(path);
  if (target.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(target.parent_path(), ec);
    if (ec) throw io_failed(path, "cannot create directory: " + ec.message());
  }
  // Keep the extension last: some writers (gmsh, CGAL) choose the format from it.
  const std::string tmp = (target.parent_path() / (".tmp." + std::to_string(::getpid()) + "." +
                                                   target.filename().string())).string();
  try {
    writer(tmp);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  std::error_code ec;
  if (!fs::exists(tmp, ec)) throw io_failed(path, "writer produced no file");
  fs::rename(tmp, target, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw io_failed(path, "cannot rename temporary file: " + ec.message());
  }
}

void write_all_or_none(const std::vector<Output>& outputs) {
  std::vector<std::string> written;
  try {
    for (const Output& o : outputs) {
      if (o.path.empty()) continue;
      o.write();
      written.push_back(o.path);
    }
  } catch (...) {
    for (const std::string& p : written) std::remove(p.c_str());
    throw;
  }
}

void write_text_atomic(const std::string& path, const std::string& text) {
  write_atomic(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.flush();
    if (!out) throw io_failed(path, "write failed");
  });
}

std::string read_text(const std::string& path) {
  require_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw bad_input(path, "cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace pipeline
