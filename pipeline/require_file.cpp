// require_file: see require_file.h.
#include "pipeline/require_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "pipeline/error.h"

namespace pipeline {

void require_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw bad_input(path, "no such file");
  if (fs::is_directory(path, ec)) throw bad_input(path, "is a directory, expected a file");
  // /dev/zero was read until memory ran out, and a pipe with no writer blocked the stage.
  if (!fs::is_regular_file(path, ec)) throw bad_input(path, "not a regular file (a device, pipe or socket)");
  if (fs::file_size(path, ec) == 0) throw bad_input(path, "file is empty");
  // A file the user may not read was reported by each reader as its first failure: "not a PLY
  // file (no 'ply' magic)", "not a gmsh mesh", "cannot open file" (sweep P).
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw bad_input(path, std::string("cannot be read: ") + std::strerror(errno));
  ::close(fd);
}

}  // namespace pipeline
