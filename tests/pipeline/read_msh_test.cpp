// pipeline::read_msh: nodes once each, groups with 0-based connectivity, and one bad-input line
// naming the file for what gmsh accepts but the stages cannot use.
#include <gtest/gtest.h>

#include <omp.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "../bad_input_message.h"
#include "../scratch_dir.h"
#include "pipeline/error.h"
#include "pipeline/read_msh.h"
#include "pipeline/require_file.h"

namespace {

// Two triangles on four nodes (tags 10..13) in a group named "skin", their shared edge in an
// unnamed line group; `x_of_node_11` and `shared_edge_end` let a test break it.
std::string square_msh(const std::string& x_of_node_11 = "1", int shared_edge_end = 13) {
  return "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
         "$PhysicalNames\n1\n2 1 \"skin\"\n$EndPhysicalNames\n"
         "$Entities\n0 1 1 0\n1 0 0 0 1 1 0 1 2 0\n1 0 0 0 1 1 0 1 1 0\n$EndEntities\n"
         "$Nodes\n1 4 10 13\n2 1 0 4\n10\n11\n12\n13\n0 0 0\n" + x_of_node_11 + " 0 0\n1 1 0\n0 1 0\n$EndNodes\n"
         "$Elements\n2 3 1 3\n2 1 2 2\n1 10 11 12\n2 10 12 13\n1 1 1 1\n3 10 " + std::to_string(shared_edge_end) +
         "\n$EndElements\n";
}

// The message of the bad-input error read_msh throws, or "no error".
std::string msh_error_of(const std::string& path) {
  return bad_input_message([&] { pipeline::read_msh(path); });
}

}  // namespace

TEST(read_msh, nodes_once_and_groups_with_zero_based_connectivity) {
  const pipeline::MshFile f = pipeline::read_msh(scratch_file("square.msh", square_msh()));
  ASSERT_EQ(f.n_nodes(), 4u);
  EXPECT_EQ(f.node_tags, (std::vector<std::size_t>{10, 11, 12, 13}));
  ASSERT_EQ(f.xyz.size(), 12u);
  EXPECT_EQ(f.xyz[3], 1.0);  // node 11 at (1, 0, 0)
  EXPECT_EQ(f.xyz[7], 1.0);  // node 12 at (1, 1, 0)
  ASSERT_EQ(f.groups.size(), 2u);
  const pipeline::MshGroup* skin = nullptr;
  const pipeline::MshGroup* line = nullptr;
  for (const auto& g : f.groups) (g.dim == 2 ? skin : line) = &g;
  ASSERT_TRUE(skin && line);
  EXPECT_EQ(skin->name, "skin");
  EXPECT_EQ(line->name, "");  // unnamed: the caller names it
  EXPECT_EQ(line->tag, 2);
  ASSERT_EQ(skin->elements.size(), 1u);
  EXPECT_EQ(skin->elements[0].gmsh_type, 2);
  EXPECT_EQ(skin->elements[0].nodes_per_element, 3);
  EXPECT_EQ(skin->elements[0].conn, (std::vector<int>{0, 1, 2, 0, 2, 3}));
  ASSERT_EQ(line->elements.size(), 1u);
  EXPECT_EQ(line->elements[0].nodes_per_element, 2);
  EXPECT_EQ(line->elements[0].conn, (std::vector<int>{0, 3}));
}

// gmsh lists nodes entity by entity, and surface_mesh's curve and point entities are numbered in
// an order that changes between runs (gmsh 4.8's createTopology sorts by pointer): the reader's
// node order is the tags', so the same mesh listed in another order reads the same.
TEST(read_msh, nodes_in_tag_order_whatever_order_the_file_lists_them) {
  const pipeline::MshFile listed_in_order = pipeline::read_msh(scratch_file("square_in_order.msh", square_msh()));
  std::string text = square_msh();
  const std::string in_order = "10\n11\n12\n13\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
  ASSERT_NE(text.find(in_order), std::string::npos);
  text.replace(text.find(in_order), in_order.size(), "12\n13\n10\n11\n1 1 0\n0 1 0\n0 0 0\n1 0 0\n");
  const pipeline::MshFile shuffled = pipeline::read_msh(scratch_file("square_shuffled.msh", text));
  EXPECT_EQ(shuffled.node_tags, (std::vector<std::size_t>{10, 11, 12, 13}));
  EXPECT_EQ(shuffled.xyz, listed_in_order.xyz);
  ASSERT_EQ(shuffled.groups.size(), listed_in_order.groups.size());
  for (std::size_t g = 0; g < shuffled.groups.size(); ++g) {
    ASSERT_EQ(shuffled.groups[g].elements.size(), 1u);
    EXPECT_EQ(shuffled.groups[g].elements[0].conn, listed_in_order.groups[g].elements[0].conn);
  }
}

// A tag listed twice at different coordinates (a mesh merged by hand) is refused; its first
// coordinates had won without a word. Listed twice at the same place, as gmsh lists a node on
// the boundary of two entities, it is one node.
TEST(read_msh, a_node_defined_twice_at_different_places_is_refused) {
  const std::string once = "$Nodes\n1 4 10 13\n2 1 0 4\n10\n11\n12\n13\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
  std::string text = square_msh();
  ASSERT_NE(text.find(once), std::string::npos);
  for (const std::string& again : {std::string("1 1 0"), std::string("5 5 5")}) {
    std::string twice = text;
    twice.replace(twice.find(once), once.size(),
                  "$Nodes\n1 5 10 13\n2 1 0 5\n10\n11\n12\n13\n12\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n" + again + "\n");
    const std::string path = scratch_file("square_twice.msh", twice);
    if (again == "1 1 0") {
      EXPECT_EQ(msh_error_of(path), "no error");
      EXPECT_EQ(pipeline::read_msh(path).n_nodes(), 4u);
    } else {
      EXPECT_EQ(msh_error_of(path), path + ": node 12 is defined twice, at different coordinates");
    }
  }
}

TEST(read_msh, bad_files_give_one_line_naming_the_file) {
  const std::string missing = (scratch_dir() / "missing.msh").string();
  EXPECT_EQ(msh_error_of(missing), missing + ": no such file");
  const std::string empty = scratch_file("empty.msh", "");
  EXPECT_EQ(msh_error_of(empty), empty + ": file is empty");
  const std::string folder = (scratch_dir() / "folder.msh").string();
  std::filesystem::create_directories(folder);
  EXPECT_EQ(msh_error_of(folder), folder + ": is a directory, expected a file");
  // a device was read until memory ran out (require_file, shared by every reader)
  EXPECT_EQ(msh_error_of("/dev/zero"), "/dev/zero: not a regular file (a device, pipe or socket)");
  const std::string header_only = scratch_file("header_only.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
  EXPECT_EQ(msh_error_of(header_only), header_only + ": no nodes (empty, or not a gmsh mesh)");
  const std::string cut = square_msh().substr(0, 200);
  const std::string truncated = scratch_file("truncated.msh", cut);
  EXPECT_EQ(msh_error_of(truncated), truncated + ": section $Nodes (line 13) is not closed by $EndNodes (truncated file?)");
  // gmsh reads "nan" as a number: the reader has to name the node
  const std::string nan = scratch_file("nan.msh", square_msh("nan"));
  EXPECT_EQ(msh_error_of(nan), nan + ": node 11 has a non-finite coordinate");
  const std::string inf = scratch_file("inf.msh", square_msh("inf"));
  EXPECT_EQ(msh_error_of(inf), inf + ": node 11 has a non-finite coordinate");
  const std::string dangling = scratch_file("dangling.msh", square_msh("1", 99));
  const std::string dangling_error = msh_error_of(dangling);
  EXPECT_NE(dangling_error.find(dangling + ": "), std::string::npos) << dangling_error;
  EXPECT_NE(dangling_error.find("99"), std::string::npos) << dangling_error;
  // gmsh reads a $Nodes section without its $EndNodes silently and skips to the end of the file:
  // the elements were lost and layers wrote an empty model with exit 0.
  std::string text = square_msh();
  const std::string no_end_nodes = scratch_file("no_end_nodes.msh", text.erase(text.find("$EndNodes\n"), 10));
  EXPECT_EQ(msh_error_of(no_end_nodes),
            no_end_nodes + ": section $Nodes (line 13) is not closed by $EndNodes before line 24 ($Elements)");
  text = square_msh();
  const std::string no_end = scratch_file("no_end.msh", text.erase(text.find("$EndElements\n")));
  EXPECT_EQ(msh_error_of(no_end),
            no_end + ": section $Elements (line 25) is not closed by $EndElements (truncated file?)");
  for (const std::string& path : {empty, folder, header_only, truncated, nan, inf, dangling, no_end_nodes, no_end}) {
    const std::string e = msh_error_of(path);
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

// gmsh trusts what it reads: any text not starting with $MeshFormat it runs as a .geo script
// (a System line ran a shell command), a block declaring 4e9 elements aborted libgmsh 4.8 and a
// negative node tag crashed getElements. read_msh checks these before gmsh sees the file.
TEST(read_msh, refuses_a_script_impossible_counts_and_bad_tags_before_gmsh_reads_them) {
  const std::filesystem::path witness = scratch_dir() / "script_ran";
  std::filesystem::remove(witness);
  const std::string script = scratch_file("script.msh", "System \"touch " + witness.string() + "\";\n");
  EXPECT_EQ(msh_error_of(script), script + ": not a gmsh mesh: its first line is 'System \"touch " +
                                      witness.string().substr(0, 26) + "...', expected $MeshFormat");
  EXPECT_FALSE(std::filesystem::exists(witness));
  const std::string text = scratch_file("text.msh", "hello world\n");
  EXPECT_EQ(msh_error_of(text), text + ": not a gmsh mesh: its first line is 'hello world', expected $MeshFormat");

  auto replaced = [](std::string s, const std::string& from, const std::string& to) {
    return s.replace(s.find(from), from.size(), to);
  };
  const std::string huge = scratch_file("huge.msh", replaced(square_msh(), "1 1 1 1\n3 10", "1 1 1 4000000000\n3 10"));
  EXPECT_EQ(msh_error_of(huge),
            huge + ": line 30: a block of 4000000000 elements, but its section has 1 line left (truncated or corrupt file?)");
  const std::string huge_nodes = scratch_file("huge_nodes.msh", replaced(square_msh(), "2 1 0 4\n", "2 1 0 4000000000\n"));
  EXPECT_EQ(msh_error_of(huge_nodes), huge_nodes +
                                          ": line 15: a block of 4000000000 nodes, but its section has 8 lines left "
                                          "(truncated or corrupt file?)");
  const std::string negative = scratch_file("negative.msh", replaced(square_msh(), "3 10 13", "3 10 -3"));
  EXPECT_EQ(msh_error_of(negative), negative + ": line 31: tag '-3' is not a positive integer");
  const std::string word = scratch_file("word.msh", replaced(square_msh(), "3 10 13", "3 10 x"));
  EXPECT_EQ(msh_error_of(word), word + ": line 31: 'x' is not an integer");
  const std::string extra = scratch_file("extra.msh", replaced(square_msh(), "3 10 13\n", "3 10 13\n4 11 12\n"));
  EXPECT_EQ(msh_error_of(extra), extra + ": line 32: more lines in $Elements than its blocks declare");
  const std::string v22 = scratch_file("v22.msh",
                                       "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n$EndNodes\n");
  EXPECT_EQ(msh_error_of(v22), v22 + ": line 5: $Nodes declares 3 nodes but holds 2 lines");
  // A 2.2 file (gmsh's own older ASCII format) reads, one-node point elements and a file starting
  // with $Comments included.
  std::string v22_text = "$Comments\nmade by hand\n$EndComments\n$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                         "$PhysicalNames\n2\n0 1 \"tip\"\n2 2 \"skin\"\n$EndPhysicalNames\n"
                         "$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
                         "$Elements\n2\n1 15 2 1 1 1\n2 2 2 2 1 1 2 3\n$EndElements\n";
  const std::string v22_good = scratch_file("v22_good.msh", v22_text);
  EXPECT_EQ(msh_error_of(v22_good), "no error");
  EXPECT_EQ(pipeline::read_msh(v22_good).groups.size(), 2u);
  const std::string v22_negative =
      scratch_file("v22_negative.msh", v22_text.replace(v22_text.find("1 15 2 1 1 1"), 12, "-1 15 2 1 1 1"));
  EXPECT_EQ(msh_error_of(v22_negative), v22_negative + ": line 20: tag '-1' is not a positive integer");
  for (const std::string& path : {script, text, huge, huge_nodes, negative, word, extra, v22})
    EXPECT_EQ(msh_error_of(path).find('\n'), std::string::npos);
}

// gmsh sets the OpenMP thread count when it initialises and reads; the caller's count comes back.
TEST(read_msh, leaves_the_openmp_thread_count_as_it_found_it) {
  const std::string path = scratch_file("square_threads.msh", square_msh());
  const int before = omp_get_max_threads();
  omp_set_num_threads(3);
  pipeline::read_msh(path);
  EXPECT_EQ(omp_get_max_threads(), 3);
  omp_set_num_threads(before);
}

// The section check reads lines as gmsh does: a file saved with Windows line ends still reads.
TEST(read_msh, reads_a_file_with_windows_line_ends) {
  std::string crlf;
  for (char c : square_msh()) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  const pipeline::MshFile f = pipeline::read_msh(scratch_file("square_crlf.msh", crlf));
  EXPECT_EQ(f.n_nodes(), 4u);
  EXPECT_EQ(f.groups.size(), 2u);
  // ... and is checked: with the "\r" kept, line 1 would not read as "$MeshFormat" and the check
  // would skip the file.
  const std::string cut = scratch_file("square_crlf_no_end_nodes.msh", crlf.erase(crlf.find("$EndNodes\r\n"), 11));
  EXPECT_EQ(msh_error_of(cut).rfind(cut + ": section $Nodes (line 13) is not closed by $EndNodes", 0), 0u)
      << msh_error_of(cut);
}

// Stages find groups by name, and gmsh keeps one name per group: a name given twice, or a group
// named twice, lost a group without a word (layers crashed on a surface with two "forehead"
// groups; a respirator's rim read as its inner face).
TEST(read_msh, a_group_named_twice_or_a_name_given_twice_is_refused) {
  std::string text = square_msh();
  const std::string names = "$PhysicalNames\n1\n2 1 \"skin\"\n$EndPhysicalNames\n";
  const auto with_names = [&](const std::string& file, const std::string& list) {
    std::string t = text;
    return scratch_file(file, t.replace(t.find(names), names.size(), list));
  };
  const std::string twice = with_names("named_twice.msh", "$PhysicalNames\n2\n2 1 \"skin\"\n2 1 \"fat\"\n$EndPhysicalNames\n");
  EXPECT_EQ(msh_error_of(twice), twice + ": line 7: physical group 1 of dimension 2 is named twice, \"skin\" and \"fat\"");
  const std::string shared = with_names("one_name.msh", "$PhysicalNames\n2\n2 1 \"skin\"\n2 3 \"skin\"\n$EndPhysicalNames\n");
  EXPECT_EQ(msh_error_of(shared), shared + ": line 7: two physical groups of dimension 2 are named \"skin\" (tags 1 and 3)");
  // one name in two dimensions is two groups a stage tells apart
  const std::string dims = with_names("two_dims.msh", "$PhysicalNames\n2\n2 1 \"skin\"\n1 2 \"skin\"\n$EndPhysicalNames\n");
  EXPECT_EQ(msh_error_of(dims), "no error");

}

// A file the user may not read gets the system's reason from require_file, which every reader
// calls first: each reader had reported its own first failure instead ("not a PLY file (no 'ply'
// magic)", "not a gmsh mesh: its first line is ''", "cannot open file"; sweep P). Root reads any
// file, so under root the check runs in a child as nobody (uid 65534), on a file in a folder
// anyone may enter.
TEST(require_file, a_file_that_cannot_be_read_gives_the_systems_reason) {
  char dir_template[] = "/tmp/require_file_XXXXXX";
  ASSERT_NE(mkdtemp(dir_template), nullptr);
  const std::string dir = dir_template, locked = dir + "/locked.msh";
  ASSERT_EQ(chmod(dir.c_str(), 0755), 0);
  { std::FILE* f = std::fopen(locked.c_str(), "w"); ASSERT_NE(f, nullptr); std::fputs("$MeshFormat\n", f); std::fclose(f); }
  ASSERT_EQ(chmod(locked.c_str(), 0), 0);
  const auto error_of = [&] { return bad_input_message([&] { pipeline::require_file(locked); }); };
  std::string error;
  if (geteuid() != 0) {
    error = error_of();
  } else {
    int out[2];
    ASSERT_EQ(pipe(out), 0);
    const pid_t child = fork();
    if (child == 0) {
      close(out[0]);
      if (setgid(65534) != 0 || setuid(65534) != 0) _exit(3);
      const std::string e = error_of();
      if (write(out[1], e.data(), e.size()) < 0) _exit(4);
      _exit(0);
    }
    close(out[1]);
    char buf[512];
    for (ssize_t n; (n = read(out[0], buf, sizeof buf)) > 0;) error.append(buf, std::size_t(n));
    close(out[0]);
    int status = 0;
    waitpid(child, &status, 0);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  }
  std::filesystem::remove_all(dir);
  EXPECT_EQ(error, locked + ": cannot be read: Permission denied");
}
