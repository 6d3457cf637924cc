#include "pipeline/atomic_write.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
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
    errno = 0;  // so why_write_failed gives this write's reason, not an earlier call's
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
  } catch (const Error& e) {
    for (const std::string& p : written) std::remove(p.c_str());
    if (written.empty()) throw;
    // Say so: `generate_scan --out x.ply --clean-mesh c.obj` failing on c.obj named only c.obj,
    // and x.ply, the user's earlier copy included, was gone.
    std::string removed;
    for (const std::string& p : written) removed += (removed.empty() ? "" : ", ") + p;
    throw Error(e.kind, std::string(e.what()) + " (" + removed + ", written before it, removed: a stage's outputs "
                                                 "are all or none)");
  } catch (...) {
    for (const std::string& p : written) std::remove(p.c_str());
    throw;
  }
}

std::string nearest_existing_folder(const std::string& path) {
  std::error_code ec;
  fs::path dir(path);
  while (!dir.empty() && dir != dir.parent_path() && fs::symlink_status(dir, ec).type() == fs::file_type::not_found)
    dir = dir.parent_path();
  return dir.empty() ? "." : dir.string();
}

void require_writable_outputs(const std::vector<std::string>& paths) {
  for (const std::string& path : paths) {
    if (path.empty()) continue;
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw io_failed(path, "is a folder, not a file");
    const std::string dir = nearest_existing_folder(fs::path(path).parent_path().string());
    std::string probe = (fs::path(dir) / ".writable.XXXXXX").string();  // a name of its own, as mkstemp picks it
    const int fd = ::mkstemp(probe.data());
    if (fd < 0) throw io_failed(path, "cannot write in " + dir + ": " + std::strerror(errno));
    ::close(fd);
    ::unlink(probe.c_str());
  }
}

void write_text_atomic(const std::string& path, const std::string& text) {
  write_atomic(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.flush();
    if (!out) throw io_failed(path, "write failed: " + why_write_failed());
  });
}

std::string why_write_failed() { return errno ? std::strerror(errno) : "write error"; }

std::string read_text(const std::string& path) {
  require_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw bad_input(path, "cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace pipeline
