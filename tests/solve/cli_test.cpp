// The `solve` program end to end: a good run writes every output; bad inputs give one error line,
// a non-zero exit and no results file; a restart continues; the meshio converter reads the results.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "solve/load_model.h"
#include "solve/make_block.h"
#include "solve/write_results.h"
#include "../file_text.h"
#include "../last_line.h"
#include "../run_command.h"
#include "../scratch_dir.h"

namespace {
namespace fs = std::filesystem;

struct CliCase {
  std::string dir;
  CliCase() {
    dir = (scratch_dir() / "cli").string();
    fs::remove_all(dir);
    fs::create_directories(dir);
    solve::BlockSpec b;
    b.type = solve::ElementType::wedge6;
    b.nx = 3; b.ny = 3; b.nz = 3;
    b.size = {3, 3, 3};
    solve::write_mesh_msh(solve::make_block(b, {"skin", 1.2e-3, 0.6, 0.45, false}), dir + "/block.msh");
  }
  void write(const std::string& name, const std::string& text) const { std::ofstream(dir + "/" + name) << text; }
  std::string read(const std::string& name) const { return file_text(dir + "/" + name); }
  // Runs a command; returns its exit code; stderr in dir/err.txt.
  int sh(const std::string& cmd) const {
    return run_command(cmd + " > " + dir + "/out.txt 2> " + dir + "/err.txt");
  }
  int solve(const std::string& deck, const std::string& out, const std::string& extra = "") const {
    return sh(std::string(BIN_DIR) + "/solve --model " + dir + "/block.msh --deck " + dir + "/" + deck +
              " --out-dir " + dir + "/" + out + " " + extra);
  }
};

const char* kDeck = R"({
  "materials": {"skin": {"density": 1.2e-3, "E": 0.6, "nu": 0.45}},
  "parts": [{"group": "block", "material": "skin"}],
  "fixed": [{"group": "zmin", "dofs": "xyz"}],
  "prescribed": [{"group": "zmax", "type": "velocity", "dof": "z", "curve": [[0, 0], [0.5, -0.2], [END, -0.2]]}],
  "control": {"end_time": END, "damping_alpha": 0.5, "output_interval": 0.25},
  "output": {"history_groups": ["zmax"]}
})";

std::string deck(double end) {
  std::string d = kDeck;
  for (std::size_t p; (p = d.find("END")) != std::string::npos;) d.replace(p, 3, std::to_string(end));
  return d;
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t p = 0; (p = text.find(what, p)) != std::string::npos; p += what.size()) ++n;
  return n;
}

}  // namespace

// Ctrl-C (SIGINT), SIGTERM or SIGHUP (a closed terminal) killed a run and left its frames' temporary file beside the results
// of an earlier run in the same folder, which looked like this run's (and stage II would have
// started from the old state.bin). Now an earlier run's outputs are removed when a run starts,
// and a signal stops the run after its step: exit 130, one line, nothing of either run left.
TEST(solve_cli, a_run_stopped_by_a_signal_leaves_no_outputs_of_its_own_or_of_an_earlier_run) {
  CliCase c;
  c.write("short.json", deck(1.0));
  std::string long_deck = deck(1e5);  // about 5 million steps: minutes
  const std::string every_quarter = "\"output_interval\": 0.25";
  long_deck.replace(long_deck.find(every_quarter), every_quarter.size(), "\"output_interval\": 1000");
  c.write("long.json", long_deck);
  const std::map<std::string, std::string> said = {{"INT", "SIGINT (Ctrl-C)"},
                                                    {"TERM", "SIGTERM"},
                                                    {"HUP", "SIGHUP (the terminal closed)"}};
  for (const auto& [signal, name] : said) {
    ASSERT_EQ(c.solve("short.json", "stopped"), 0) << c.read("err.txt");
    for (const char* f : {"results.msh", "energy.csv", "forces.csv", "state.bin"})
      ASSERT_TRUE(fs::exists(c.dir + "/stopped/" + f)) << f;
    // timeout sends the signal after 2 s and returns the run's own exit status
    EXPECT_EQ(c.sh("timeout --preserve-status -s " + signal + " 2 " + std::string(BIN_DIR) + "/solve --model " + c.dir +
                   "/block.msh --deck " + c.dir + "/long.json --out-dir " + c.dir + "/stopped"),
              130)
        << c.read("err.txt");
    std::string last;
    std::istringstream err(c.read("err.txt"));
    for (std::string line; std::getline(err, line);) last = line;
    EXPECT_EQ(last.rfind("solve: ", 0), 0u) << last;
    EXPECT_NE(last.find(": stopped by " + name + " at t = "), std::string::npos) << last;
    EXPECT_NE(last.find("no results written"), std::string::npos) << last;
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(c.dir + "/stopped")) left.push_back(e.path().filename().string());
    EXPECT_TRUE(left.empty()) << left.front();
  }
}

// Two runs into one --out-dir shared the frames file and removed each other's outputs: a finished
// run's results.msh was deleted by the other, which then failed with a file system error (sweep
// P). Now the second is refused (exit 2, one line) while the first runs; the first's lock goes
// with it (stopped here by SIGINT, it leaves the folder empty), and the folder is free again.
TEST(solve_cli, a_second_run_into_a_busy_out_dir_is_refused) {
  CliCase c;
  c.write("short.json", deck(1.0));
  std::string long_deck = deck(1e5);
  const std::string every_quarter = "\"output_interval\": 0.25";
  long_deck.replace(long_deck.find(every_quarter), every_quarter.size(), "\"output_interval\": 1000");
  c.write("long.json", long_deck);
  ASSERT_EQ(run_command("(timeout --preserve-status -s INT 6 " + std::string(BIN_DIR) + "/solve --model " + c.dir +
                        "/block.msh --deck " + c.dir + "/long.json --out-dir " + c.dir + "/busy > /dev/null 2> " + c.dir +
                        "/first_err.txt; echo $? > " + c.dir + "/first_rc.txt) > /dev/null 2>&1 &"),
            0);
  for (int k = 0; k < 400 && !fs::exists(c.dir + "/busy/.solve.lock"); ++k) run_command("sleep 0.05");
  ASSERT_TRUE(fs::exists(c.dir + "/busy/.solve.lock"));
  EXPECT_EQ(c.solve("short.json", "busy"), 2) << c.read("err.txt");
  EXPECT_EQ(count(c.read("err.txt"), "another solve"), 1) << c.read("err.txt");
  EXPECT_EQ(last_line(c.read("err.txt")).rfind("solve: " + c.dir + "/busy: another solve is writing its outputs in this folder now", 0), 0u)
      << c.read("err.txt");
  for (int k = 0; k < 1200 && !fs::exists(c.dir + "/first_rc.txt"); ++k) run_command("sleep 0.05");
  ASSERT_TRUE(fs::exists(c.dir + "/first_rc.txt"));
  EXPECT_EQ(std::atoi(c.read("first_rc.txt").c_str()), 130) << c.read("first_err.txt");
  EXPECT_TRUE(fs::is_empty(c.dir + "/busy")) << fs::directory_iterator(c.dir + "/busy")->path();
  ASSERT_EQ(c.solve("short.json", "busy"), 0) << c.read("err.txt");
  EXPECT_TRUE(fs::exists(c.dir + "/busy/results.msh"));
  EXPECT_FALSE(fs::exists(c.dir + "/busy/.solve.lock"));
}

// gmsh does not see its write errors: under a file size limit (as on a full disk) results.msh
// came out cut short with exit 0, beside a complete state.bin. Now the run exits 4 naming it and
// leaves none of its outputs, nor its frames' temporary file.
TEST(solve_cli, a_file_size_limit_leaves_no_outputs) {
  CliCase c;
  c.write("deck.json", deck(1.0));
  // SIGXFSZ ignored, so a write past the limit fails with EFBIG, as on a full disk; 30 blocks of
  // 1 kB hold state.bin and the CSVs but not the results (~100 kB here).
  ASSERT_EQ(c.sh("bash -c \"trap '' XFSZ; ulimit -f 30; exec " + std::string(BIN_DIR) + "/solve --model " + c.dir +
                 "/block.msh --deck " + c.dir + "/deck.json --out-dir " + c.dir + "/limited\""),
            4)
      << c.read("err.txt");
  const std::string err = c.read("err.txt");
  EXPECT_NE(err.find("solve: " + c.dir + "/limited/results.msh: written incompletely ("), std::string::npos) << err;
  EXPECT_TRUE(fs::is_empty(c.dir + "/limited")) << fs::directory_iterator(c.dir + "/limited")->path();
  // Without the trap the kernel's SIGXFSZ killed the stage mid-write (exit 153, no message, its
  // temporary file left); every stage now ignores it itself (pipeline::run_main).
  ASSERT_EQ(c.sh("bash -c \"ulimit -f 30; exec " + std::string(BIN_DIR) + "/solve --model " + c.dir + "/block.msh --deck " +
                 c.dir + "/deck.json --out-dir " + c.dir + "/limited_no_trap\""),
            4)
      << c.read("err.txt");
  EXPECT_TRUE(fs::is_empty(c.dir + "/limited_no_trap")) << fs::directory_iterator(c.dir + "/limited_no_trap")->path();
  // A run restarted from the state in its own output folder keeps that state when its outputs
  // fail (state.bin is written last), and removes the earlier run's other outputs.
  ASSERT_EQ(c.solve("deck.json", "again"), 0) << c.read("err.txt");
  const std::string state = c.read("again/state.bin");
  c.write("deck2.json", deck(2.0));
  EXPECT_EQ(c.sh("bash -c \"trap '' XFSZ; ulimit -f 30; exec " + std::string(BIN_DIR) + "/solve --model " + c.dir +
                 "/block.msh --deck " + c.dir + "/deck2.json --out-dir " + c.dir + "/again --restart " + c.dir +
                 "/again/state.bin\""),
            4)
      << c.read("err.txt");
  EXPECT_EQ(c.read("again/state.bin"), state);
  for (const char* f : {"results.msh", "energy.csv", "forces.csv"}) EXPECT_FALSE(fs::exists(c.dir + "/again/" + f)) << f;
  // A limit the frames pass during the run (4 kB: the first frames) stops it there, with the
  // system's reason, instead of stepping on to the end (sweep P: a disk filled 6 s into a run
  // was reported after its last step).
  c.write("long.json", deck(20.0));
  ASSERT_EQ(c.sh("bash -c \"trap '' XFSZ; ulimit -f 4; exec " + std::string(BIN_DIR) + "/solve --model " + c.dir +
                 "/block.msh --deck " + c.dir + "/long.json --out-dir " + c.dir + "/limited_early\""),
            4)
      << c.read("err.txt");
  const std::string early = last_line(c.read("err.txt"));
  EXPECT_EQ(early.rfind("solve: " + c.dir + "/limited_early/results.msh: frame ", 0), 0u) << early;
  EXPECT_NE(early.find(" could not be written: File too large; no results written"), std::string::npos) << early;
  const std::string frame_at = "results.msh: frame ";
  const int stopped_at = std::atoi(early.c_str() + early.find(frame_at) + frame_at.size());
  std::printf("stopped at frame %d of 81: %s\n", stopped_at, early.c_str());
  EXPECT_LT(stopped_at, 40);  // of 81 (every 0.25 ms to 20 ms): not at the end
  EXPECT_TRUE(fs::is_empty(c.dir + "/limited_early")) << fs::directory_iterator(c.dir + "/limited_early")->path();
}

// A model or deck kept in the output folder under an output's name was deleted by a diverging
// run and overwritten by a sound one. Now refused before the run (exit 1), the file untouched; a
// restart from the folder's own state.bin is still allowed (previous test).
TEST(solve_cli, an_input_named_as_an_output_in_the_out_dir_is_refused_and_kept) {
  CliCase c;
  c.write("deck.json", deck(1.0));
  fs::create_directories(c.dir + "/kept");
  fs::copy_file(c.dir + "/block.msh", c.dir + "/kept/results.msh");
  const std::string model = c.read("kept/results.msh");
  EXPECT_EQ(c.sh(std::string(BIN_DIR) + "/solve --model " + c.dir + "/kept/results.msh --deck " + c.dir +
                 "/deck.json --out-dir " + c.dir + "/kept"),
            1);
  const std::string err = c.read("err.txt");
  EXPECT_EQ(count(err, "\n"), 2) << err;  // the options line and the error
  EXPECT_NE(err.find("--model '" + c.dir + "/kept/results.msh' is the same file as the output " + c.dir + "/kept/results.msh: "), std::string::npos) << err;
  EXPECT_EQ(c.read("kept/results.msh"), model);
  c.write("kept/energy.csv", deck(1.0));
  EXPECT_EQ(c.sh(std::string(BIN_DIR) + "/solve --model " + c.dir + "/block.msh --deck " + c.dir +
                 "/kept/energy.csv --out-dir " + c.dir + "/kept/"),
            1)
      << c.read("err.txt");
  EXPECT_NE(c.read("err.txt").find("--deck '"), std::string::npos) << c.read("err.txt");
  EXPECT_EQ(c.read("kept/energy.csv"), deck(1.0));
  EXPECT_FALSE(fs::exists(c.dir + "/kept/state.bin"));
  // A next stage run into the folder of the state its deck starts from (stage II with --out-dir
  // stage1): refused, the earlier stage's results and state kept. It had deleted them and
  // replaced state.bin with its own, exit 0. --restart still continues a run in place.
  ASSERT_EQ(c.solve("deck.json", "stage1"), 0) << c.read("err.txt");
  const std::string state = c.read("stage1/state.bin"), results = c.read("stage1/results.msh");
  std::string next = deck(2.0);
  next.replace(next.find("\"control\""), 0, "\"initial_state\": {\"file\": \"stage1/state.bin\", \"reset_time\": true},\n  ");
  c.write("next.json", next);
  EXPECT_EQ(c.solve("next.json", "stage1"), 1);
  EXPECT_NE(c.read("err.txt").find("holds " + c.dir + "/stage1/state.bin, the state this deck's initial_state starts from"),
            std::string::npos)
      << c.read("err.txt");
  EXPECT_EQ(c.read("stage1/state.bin"), state);
  EXPECT_EQ(c.read("stage1/results.msh"), results);
  EXPECT_EQ(c.solve("next.json", "stage2"), 0) << c.read("err.txt");
  // a next stage before the earlier one: said so (it was only "stage1/state.bin: no such file")
  std::string early = next;
  early.replace(early.find("stage1/state.bin"), 16, "absent/state.bin");
  c.write("early.json", early);
  EXPECT_EQ(c.solve("early.json", "stage3"), 2);
  EXPECT_NE(c.read("err.txt").find("absent/state.bin: no such file: the deck's initial_state names it (relative to "
                                   "the deck's folder); run the stage that writes it first"),
            std::string::npos)
      << c.read("err.txt");
  EXPECT_EQ(c.solve("deck.json", "stage1", "--restart " + c.dir + "/stage1/state.bin --end-time-ms 1.5"), 0)
      << c.read("err.txt");
}

// An output interval far below the time step looped ~1e9 times a step to find the next output
// time; now it gives one frame per step (at most), and a history row per step.
TEST(solve_cli, an_output_interval_below_the_time_step_gives_a_frame_per_step) {
  CliCase c;
  std::string d = deck(1.0);
  d.replace(d.find("\"output_interval\": 0.25"), 23, "\"output_interval\": 1e-12, \"history_interval\": 1e-12");
  c.write("tiny.json", d);
  ASSERT_EQ(c.solve("tiny.json", "tiny"), 0) << c.read("err.txt");
  const std::string err = c.read("err.txt");
  const std::size_t at = err.find(" steps, dt ");
  ASSERT_NE(at, std::string::npos) << err;
  const long steps = std::stol(err.substr(err.rfind(", ", at) + 2));
  EXPECT_GT(steps, 2);
  EXPECT_EQ(count(c.read("tiny/results.msh"), "$NodeData"), 5 * (steps + 1));  // t0 and every step
  EXPECT_EQ(count(c.read("tiny/energy.csv"), "\n"), 1 + steps);  // header, a row after every step
}

TEST(solve_cli, good_run_writes_results_state_and_histories) {
  CliCase c;
  c.write("deck.json", deck(1.0));
  ASSERT_EQ(c.solve("deck.json", "out"), 0) << c.read("err.txt");
  for (const char* f : {"results.msh", "state.bin", "energy.csv", "forces.csv"})
    EXPECT_TRUE(fs::exists(c.dir + "/out/" + f)) << f;
  // frames at 0, 0.25, 0.5, 0.75, 1.0 ms, five fields each
  EXPECT_EQ(count(c.read("out/results.msh"), "$NodeData"), 5 * 5);
  // the results open as a mesh again (same nodes)
  const solve::Model r = solve::read_msh(c.dir + "/out/results.msh");
  EXPECT_EQ(r.n_nodes(), 64u);
  // the room the run checked for before it started is an upper bound on its frames
  const std::string results = c.read("out/results.msh");
  EXPECT_LE(double(results.size() - results.find("$NodeData")), 5 * solve::node_data_bytes_max(r));
  // the pressing force shows up as a reaction on zmax (compressive: +z on the block's top)
  EXPECT_NE(c.read("out/forces.csv").find("zmax_reaction_Fz"), std::string::npos);
  // restart: continue to 2 ms from the saved state
  c.write("deck2.json", deck(2.0));
  ASSERT_EQ(c.solve("deck2.json", "out2", "--restart " + c.dir + "/out/state.bin"), 0) << c.read("err.txt");
  EXPECT_TRUE(fs::exists(c.dir + "/out2/results.msh"));
  // It starts where the first run ended, at 1 ms with the block compressed (a run that ignored
  // --restart would start at 0 with no strain energy): measured 1.0036 ms, 0.023 mJ.
  const std::string energy2 = c.read("out2/energy.csv");
  double t0_ms = -1, kinetic_mJ = -1, internal_mJ = -1;
  ASSERT_EQ(std::sscanf(energy2.c_str() + energy2.find('\n') + 1, "%lf,%lf,%lf", &t0_ms, &kinetic_mJ, &internal_mJ), 3)
      << energy2.substr(0, 200);
  EXPECT_GE(t0_ms, 1.0);
  EXPECT_LT(t0_ms, 1.1);
  EXPECT_GT(internal_mJ, 0.01);
  // --restart with a deck that ends where the state is: the way to a new stage from it is the
  // deck's initial_state, which the message says (it said "a later end_time?", as for a run
  // continued, and stage II run so was refused).
  EXPECT_EQ(c.solve("deck.json", "out3", "--restart " + c.dir + "/out/state.bin"), 2);
  EXPECT_NE(c.read("err.txt").find("--restart continues a run in its own time, to a later end_time; to start a new "
                                   "stage from this state, name it in the deck's initial_state"),
            std::string::npos)
      << c.read("err.txt");
  // --end-time-ms: a shorter trial of the same deck, without editing it
  ASSERT_EQ(c.solve("deck2.json", "short", "--end-time-ms 0.5"), 0) << c.read("err.txt");
  const std::string energy_short = c.read("short/energy.csv");
  double last_ms = 0;
  for (std::size_t at = energy_short.find('\n') + 1; at < energy_short.size(); at = energy_short.find('\n', at) + 1)
    last_ms = std::atof(energy_short.c_str() + at);
  // its last row is at the start of the last step (the tables ended one history interval early)
  EXPECT_GT(last_ms, 0.5 - 0.02);  // a step is ~0.01 ms here
  EXPECT_LT(last_ms, 0.5);
  // an --out-dir that is a file: said so (it was "cannot create the output directory")
  c.write("a_file", "x\n");
  EXPECT_EQ(c.solve("deck.json", "a_file"), 4);
  EXPECT_NE(c.read("err.txt").find("/a_file: is a file, not a directory"), std::string::npos) << c.read("err.txt");
  // meshio conversion for ParaView
  ASSERT_EQ(c.sh(std::string(SYSTEM_PYTHON) + " " + SOURCE_DIR + "/solve/msh_to_vtu.py " + c.dir +
                 "/out/results.msh " + c.dir + "/out/results.xdmf"),
            0)
      << c.read("err.txt");
  EXPECT_TRUE(fs::exists(c.dir + "/out/results.xdmf"));
  EXPECT_TRUE(fs::exists(c.dir + "/out/results.h5"));
  EXPECT_TRUE(fs::exists(c.dir + "/out/results.vtu"));
  // every cell carries its physical group's number, named in results_parts.csv (the group names
  // did not reach the .vtu: no face part could be picked in ParaView, sweep M)
  const std::string parts = c.read("out/results_parts.csv");
  EXPECT_EQ(parts.rfind("part,name\n", 0), 0u) << parts;
  // true when every cell of `type` in results.vtu carries the number results_parts.csv gives `group`
  const auto cells_carry = [&](const std::string& type, const std::string& group) {
    const auto at = parts.find("," + group + "\n");
    if (at == std::string::npos) return false;
    const std::string number = parts.substr(parts.rfind('\n', at) + 1, at - parts.rfind('\n', at) - 1);
    return c.sh(std::string(SYSTEM_PYTHON) + " -c \"import meshio, numpy; m = meshio.read('" + c.dir +
                "/out/results.vtu'); w = [d for b, d in zip(m.cells, m.cell_data['part']) if b.type == '" + type +
                "']; assert w and all((d == " + number + ").all() for d in w) and sum(map(len, w)) " +
                (type == "vertex" ? "== len(m.points)" : "> 0") + "\"") == 0;
  };
  EXPECT_TRUE(cells_carry("wedge", "block")) << parts << c.read("err.txt");
  // the last frame's values are results.msh's last $NodeData blocks, node for node (meshio keeps
  // the last block of each name): a reader that took the node-tag column for the first value (the
  // pressure showed node tags, each vector shifted by a component) passed (sweep N)
  EXPECT_EQ(c.sh(std::string(SYSTEM_PYTHON) + " -c \"import meshio, numpy; m = meshio.read('" + c.dir +
                 "/out/results.msh'); v = meshio.read('" + c.dir + "/out/results.vtu'); "
                 "assert numpy.array_equal(m.points, v.points); "
                 "assert all(numpy.array_equal(numpy.reshape(m.point_data[f], v.point_data[f].shape), v.point_data[f]) "
                 "for f in ('displacement', 'velocity', 'contact_pressure', 'von_mises')); "
                 "assert numpy.abs(v.point_data['displacement']).max() > 0\""),
            0)
      << c.read("err.txt");
  // a group of nodes only (the block's "all", every node; in a case the rim and the strap ends)
  // comes as vertex cells carrying its number
  EXPECT_TRUE(cells_carry("vertex", "all")) << parts << c.read("err.txt");
  // a file that is not gmsh (meshio 5.0 prints two lines and calls sys.exit): one line naming it
  c.write("not.msh", "this is not a mesh\n");
  EXPECT_NE(c.sh(std::string(SYSTEM_PYTHON) + " " + SOURCE_DIR + "/solve/msh_to_vtu.py " + c.dir + "/not.msh " +
                 c.dir + "/out/not.xdmf"),
            0);
  const std::string err = c.read("err.txt");
  EXPECT_NE(err.find("msh_to_vtu: " + c.dir + "/not.msh: cannot read"), std::string::npos) << err;
  EXPECT_EQ(count(err, "\n"), 1) << err;
  EXPECT_EQ(c.read("out.txt"), "");
  EXPECT_FALSE(fs::exists(c.dir + "/out/not.xdmf"));
  // an output named .vtu: refused (the time series was written there and then replaced by the
  // last frame, exit 0)
  EXPECT_NE(c.sh(std::string(SYSTEM_PYTHON) + " " + SOURCE_DIR + "/solve/msh_to_vtu.py " + c.dir +
                 "/out/results.msh " + c.dir + "/vtu/f.vtu"),
            0);
  EXPECT_NE(c.read("err.txt").find("f.vtu: the output must be named .xdmf"), std::string::npos) << c.read("err.txt");
  EXPECT_FALSE(fs::exists(c.dir + "/vtu"));
  // a missing input: one line (meshio's own ReadError had escaped read_mesh_or_raise's contract)
  EXPECT_NE(c.sh(std::string(SYSTEM_PYTHON) + " " + SOURCE_DIR + "/solve/msh_to_vtu.py " + c.dir + "/none.msh " +
                 c.dir + "/out/none.xdmf"),
            0);
  EXPECT_EQ(c.read("err.txt"), "msh_to_vtu: " + c.dir + "/none.msh: cannot read: [Errno 2] no such file: '" + c.dir +
                                   "/none.msh'\n");
}

TEST(solve_cli, bad_deck_one_error_line_no_results) {
  CliCase c;
  c.write("bad.json", R"({"materials": {"skin": {"density": 1e-3, "E": 0.6, "nu": 0.45}},
                          "parts": [{"group": "block", "material": "skin"}]})");
  EXPECT_EQ(c.solve("bad.json", "out"), 2);
  const std::string err = c.read("err.txt");
  EXPECT_NE(err.find("bad.json"), std::string::npos) << err;
  EXPECT_NE(err.find("control"), std::string::npos) << err;
  EXPECT_EQ(count(err, "solve: "), 2) << err;  // the resolved-options log line + the one error line
  EXPECT_FALSE(fs::exists(c.dir + "/out/results.msh"));
  c.write("bad2.json", "{ not json");
  EXPECT_EQ(c.solve("bad2.json", "out"), 2);
  c.write("bad3.json", deck(1.0).replace(deck(1.0).find("\"block\""), 7, "\"nope\""));
  EXPECT_EQ(c.solve("bad3.json", "out"), 2);
  EXPECT_NE(c.read("err.txt").find("nope"), std::string::npos);
  EXPECT_FALSE(fs::exists(c.dir + "/out/results.msh"));
  // An absurd end time ran for ever (and overflowed the step count of the progress line).
  c.write("bad4.json", deck(1e300));
  EXPECT_EQ(c.solve("bad4.json", "out4"), 2);
  EXPECT_FALSE(fs::exists(c.dir + "/out4"));
  EXPECT_NE(c.read("err.txt").find("bad4.json: control.end_time 1e+300 ms needs"), std::string::npos) << c.read("err.txt");
  // A dt_target in the wrong unit: 10 ms against this block's stable step of ~0.01 ms multiplies
  // the mass by ~1e6 (it ran; on the medium head, with 12.6 million % added mass).
  std::string slow = deck(1.0);
  slow.replace(slow.find("\"damping_alpha\""), 0, "\"dt_target\": 10, ");
  c.write("bad5.json", slow);
  EXPECT_EQ(c.solve("bad5.json", "out5"), 2);
  EXPECT_FALSE(fs::exists(c.dir + "/out5"));
  EXPECT_NE(c.read("err.txt").find("bad5.json: control.dt_target 10 ms adds "), std::string::npos) << c.read("err.txt");
  EXPECT_NE(c.read("err.txt").find(" times the model's mass by mass scaling, more than 1000"), std::string::npos)
      << c.read("err.txt");
  // From ~1e154 the scaled mass overflows to inf: the check compared NaN, and the run wrote NaN
  // energies with exit 0.
  std::string huge = deck(1.0);
  huge.replace(huge.find("\"damping_alpha\""), 0, "\"dt_target\": 1e160, ");
  c.write("bad6.json", huge);
  EXPECT_EQ(c.solve("bad6.json", "out6"), 2);
  EXPECT_FALSE(fs::exists(c.dir + "/out6"));
  EXPECT_NE(c.read("err.txt").find("bad6.json: control.dt_target 1e+160 ms adds inf times the model's mass"),
            std::string::npos)
      << c.read("err.txt");
  EXPECT_FALSE(fs::exists(c.dir + "/out/results.msh"));
}

// The room a frame can take: every value at its longest (" -1.23456789e-300") fills the bound
// to within its 100-byte block headers, and nothing can exceed it.
TEST(node_data_bytes_max, bounds_the_longest_frame_closely) {
  solve::BlockSpec b;
  b.type = solve::ElementType::wedge6;
  b.nx = b.ny = b.nz = 4;
  const solve::Model m = solve::make_block(b, {"skin", 1.2e-3, 0.6, 0.45, false});
  std::ostringstream out;
  for (const auto& f : m.output.node_data) {
    const int n = solve::node_data_components(f);
    append_node_data(out, m, f, 123.456789, 99999, std::vector<double>(n * m.n_nodes(), -1.23456789e-300), n);
  }
  const double bound = solve::node_data_bytes_max(m), longest = double(out.str().size());
  EXPECT_LE(longest, bound);
  EXPECT_GE(longest, bound - 100.0 * double(m.output.node_data.size()));
}

// A frame at every step of a long run needs more room than any disk has (here ~230 TB: 1,331
// nodes, 5 fields, 4.9e8 steps): refused before the run, with exit 4, one line saying what it
// needs, and no output folder. It ran and filled the disk.
TEST(solve_cli, outputs_larger_than_the_free_space_are_refused_before_the_run) {
  CliCase c;
  solve::BlockSpec b;
  b.type = solve::ElementType::wedge6;
  b.nx = b.ny = b.nz = 10;
  b.size = {3, 3, 3};
  solve::write_mesh_msh(solve::make_block(b, {"skin", 1.2e-3, 0.6, 0.45, false}), c.dir + "/fine.msh");
  std::string d = deck(1.5e6);  // 4.9e8 steps of 0.0031 ms
  const std::string every_quarter_ms = "\"output_interval\": 0.25";
  d.replace(d.find(every_quarter_ms), every_quarter_ms.size(), "\"output_interval\": 1e-9");
  c.write("every_step.json", d);
  // A file system that says nothing of its size, or has the room (a petabyte store), would let the
  // run start: then there is nothing to test here, and `timeout` stops it.
  const fs::space_info space = fs::space(c.dir);
  if (space.capacity == 0 || space.available > 2e14) GTEST_SKIP() << "no disk too small for ~230 TB here";
  EXPECT_EQ(c.sh("timeout 60 " + std::string(BIN_DIR) + "/solve --model " + c.dir + "/fine.msh --deck " + c.dir +
                 "/every_step.json --out-dir " + c.dir + "/huge"),
            4);
  const std::string err = c.read("err.txt");
  EXPECT_NE(err.find("solve: " + c.dir + "/huge: the outputs need about "), std::string::npos) << err;
  EXPECT_NE(err.find(": raise control.output_interval or history_interval"), std::string::npos) << err;
  EXPECT_EQ(count(err, "solve: "), 2) << err;  // the resolved-options log line + the one error line
  EXPECT_FALSE(fs::exists(c.dir + "/huge"));
}

TEST(solve_cli, bad_msh_one_error_line_no_results) {
  CliCase c;
  c.write("deck.json", deck(1.0));
  c.write("block.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 3\ngarbage\n");
  EXPECT_EQ(c.solve("deck.json", "out"), 2);
  EXPECT_NE(c.read("err.txt").find("block.msh"), std::string::npos) << c.read("err.txt");
  EXPECT_FALSE(fs::exists(c.dir + "/out/results.msh"));
  fs::remove(c.dir + "/block.msh");
  EXPECT_EQ(c.solve("deck.json", "out"), 2);
  EXPECT_FALSE(fs::exists(c.dir + "/out/results.msh"));
  // A NaN coordinate: gmsh reads it without complaint, so the mesh reader must name the node
  // (the model check does too, for models not read from a file).
  solve::BlockSpec b;
  solve::Model m = solve::make_block(b, {"skin", 1.2e-3, 0.6, 0.45, false});
  m.X[3 * 4 + 1] = std::nan("");
  solve::write_mesh_msh(m, c.dir + "/block.msh");
  EXPECT_EQ(c.solve("deck.json", "out"), 2);
  EXPECT_NE(c.read("err.txt").find(c.dir + "/block.msh: node 5 has a non-finite coordinate"),
            std::string::npos)
      << c.read("err.txt");
  EXPECT_FALSE(fs::exists(c.dir + "/out/results.msh"));
}

// A run of millions of steps says which part sets the step and what to check: skin E given in Pa
// (6e5 as MPa) asked stage I 9.4 million steps, and only the ETA line showed it. Stopped by
// SIGTERM after 1 s (2 million steps would take minutes).
TEST(solve_cli, millions_of_steps_name_the_part_that_sets_the_step) {
  CliCase c;
  std::string stiff = deck(20.0);
  stiff.replace(stiff.find("\"E\": 0.6"), 8, "\"E\": 6e5");
  c.write("stiff.json", stiff);
  EXPECT_EQ(c.sh("timeout --preserve-status -s TERM 1 " + std::string(BIN_DIR) + "/solve --model " + c.dir +
                 "/block.msh --deck " + c.dir + "/stiff.json --out-dir " + c.dir + "/stiff"),
            130)
      << c.read("err.txt");
  const std::string err = c.read("err.txt");
  EXPECT_NE(err.find("solve: warning: "), std::string::npos) << err;
  EXPECT_NE(err.find(" steps, more than 1000000: part 'block' (material 'skin': E 600000 MPa, nu 0.45, density 0.0012 "
                     "g/mm3) sets the step of "),
            std::string::npos)
      << err;
  c.write("deck.json", deck(1.0));
  ASSERT_EQ(c.solve("deck.json", "soft"), 0) << c.read("err.txt");
  EXPECT_EQ(c.read("err.txt").find("warning"), std::string::npos) << c.read("err.txt");
}
