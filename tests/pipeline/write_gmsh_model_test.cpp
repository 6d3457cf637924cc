// pipeline::write_gmsh_model and require_complete_msh: a .msh that the disk or a file size limit
// cut short is refused, naming the output, and leaves nothing behind (gmsh itself does not see
// its write errors, so surface_mesh, layers, assemble and solve used to finish with exit 0).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gmsh.h>

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"
#include "pipeline/gmsh_session.h"
#include "pipeline/read_msh.h"
#include "pipeline/write_gmsh_model.h"
#include "../bad_input_message.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;

namespace {

// A unit square of two triangles in a physical group "square".
void write_square(const std::string& path) {
  pipeline::GmshSession session;
  gmsh::model::add("square");
  gmsh::model::addDiscreteEntity(2, 1);
  gmsh::model::mesh::addNodes(2, 1, {1, 2, 3, 4}, {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
  gmsh::model::mesh::addElementsByType(1, 2, {1, 2}, {1, 2, 3, 1, 3, 4});
  gmsh::model::addPhysicalGroup(2, {1}, 1);
  gmsh::model::setPhysicalName(2, 1, "square");
  pipeline::write_gmsh_model(path);
}

// The io error's message of `call`, or "no error".
template <class F>
std::string io_message(F call) {
  return error_message(pipeline::ErrorKind::io, call);
}

}  // namespace

TEST(write_gmsh_model, every_cut_short_copy_is_refused_and_the_whole_file_accepted) {
  const fs::path dir = scratch_dir() / "write_gmsh_model";
  fs::create_directories(dir);
  const std::string path = (dir / "square.msh").string();
  write_square(path);
  EXPECT_EQ(pipeline::read_msh(path).n_nodes(), 4u);
  const std::string whole = pipeline::read_text(path);
  EXPECT_EQ(io_message([&] { pipeline::require_complete_msh(path, "out.msh"); }), "no error");
  // Every proper prefix, as a full disk or `ulimit -f` leaves it, down to the empty file.
  const std::string cut = (dir / "cut.msh").string();
  int refused = 0;
  for (std::size_t n = 0; n < whole.size(); ++n) {
    std::ofstream(cut, std::ios::binary) << whole.substr(0, n);
    const std::string m = io_message([&] { pipeline::require_complete_msh(cut, "out.msh"); });
    if (m.rfind("out.msh: written incompletely (" + std::to_string(n) + " bytes, ", 0) == 0 &&
        m.find("): disk full or a file size limit?") != std::string::npos)
      ++refused;
    else
      ADD_FAILURE() << n << " bytes: " << m;
  }
  EXPECT_EQ(refused, int(whole.size()));
  std::ofstream(cut, std::ios::binary) << whole.substr(0, whole.find("$Nodes") + 50);
  EXPECT_EQ(io_message([&] { pipeline::require_complete_msh(cut, "out.msh"); }),
            "out.msh: written incompletely (" + std::to_string(whole.find("$Nodes") + 50) +
                " bytes, cut inside $Nodes): disk full or a file size limit?");
}

TEST(write_gmsh_model, a_folder_it_cannot_write_in_is_named_with_the_reason) {
  // /proc takes no new files, not even from root (the tests may run as root).
  EXPECT_EQ(io_message([] { write_square("/proc/square.msh"); }).rfind("/proc/square.msh: cannot write in /proc: ", 0), 0u);
  EXPECT_FALSE(fs::exists("/proc/square.msh"));
}
