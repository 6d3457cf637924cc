#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <thread>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"
#include "pipeline/write_mesh.h"
#include "../bad_input_message.h"
#include "../scratch_dir.h"

namespace fs = std::filesystem;

TEST(write_atomic, writes_complete_file_and_creates_directories) {
  const fs::path dir = scratch_dir() / "atomic" / "sub";
  fs::remove_all(dir.parent_path());
  const std::string path = (dir / "out.txt").string();
  pipeline::write_text_atomic(path, "hello");
  EXPECT_EQ(pipeline::read_text(path), "hello");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

// A stage killed by SIGTERM, SIGINT or SIGHUP while it writes leaves neither its temporary file
// nor a new output, and the earlier output stays; it still dies of the signal (the shell and
// Make see the same status). The default action had left `.tmp.<pid>.<name>` beside the outputs.
TEST(write_atomic, a_signal_during_a_write_leaves_no_temporary_file) {
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) {
    const fs::path dir = scratch_dir() / "atomic_signal";
    fs::remove_all(dir);
    const std::string path = (dir / "out.txt").string();
    pipeline::write_text_atomic(path, "old");
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      std::signal(sig, SIG_DFL);
      pipeline::remove_temporary_files_on_signals();
      pipeline::write_atomic(path, [&](const std::string& tmp) {
        std::ofstream(tmp) << "half";
        ::raise(sig);
      });
      ::_exit(0);  // not reached
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << status;
    EXPECT_EQ(pipeline::read_text(path), "old");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1) << sig;
  }
}

// A stage run by hand and stopped (Ctrl-C) between two of its outputs left the first ones new and
// the others the earlier run's, a set no run made (sweep P). The signal now takes effect once the
// set is written: the process still dies of it, with every output new.
TEST(write_all_or_none, a_signal_between_two_outputs_takes_effect_after_the_set) {
  // raised on the writing thread, or sent to the process and taken by another thread (an OpenMP
  // worker, say), which the writing thread's signal mask does not cover
  for (const bool other_thread : {false, true}) {
    const fs::path dir = scratch_dir() / "all_or_none_signal";
    fs::remove_all(dir);
    const std::string a = (dir / "a.txt").string(), b = (dir / "b.txt").string(), c = (dir / "c.txt").string();
    for (const auto& p : {a, b, c}) pipeline::write_text_atomic(p, "old");
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      std::signal(SIGTERM, SIG_DFL);
      pipeline::remove_temporary_files_on_signals();
      std::atomic<bool> go{false};
      std::thread sender([&] {
        while (!go) std::this_thread::yield();
        if (other_thread) ::kill(::getpid(), SIGTERM);
      });
      pipeline::write_all_or_none({{a, [&] { pipeline::write_text_atomic(a, "new"); }},
                                   {b, [&] {
                                      pipeline::write_text_atomic(b, "new");
                                      if (!other_thread) ::raise(SIGTERM);
                                      go = true;
                                      std::this_thread::sleep_for(std::chrono::milliseconds(100));
                                    }},
                                   {c, [&] { pipeline::write_text_atomic(c, "new"); }}});
      sender.join();
      ::_exit(0);  // not reached: the signal is delivered when the set is written
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status << " other thread " << other_thread;
    for (const auto& p : {a, b, c}) EXPECT_EQ(pipeline::read_text(p), "new") << p << " other thread " << other_thread;
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 3);
  }
}

// A stage killed by SIGKILL (no handler sees it) left its `.tmp.<pid>.<name>` for good, a model's
// size (sweep P): the next write of that output removes it when its process is gone, and keeps
// one whose process still runs. A legal name of 250 characters was refused: the prefix took the
// temporary name past the system's 255.
TEST(write_atomic, a_dead_process_temporary_goes_and_a_long_name_is_written) {
  const fs::path dir = scratch_dir() / "stale_temporaries";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const pid_t gone = fork();
  ASSERT_GE(gone, 0);
  if (gone == 0) ::_exit(0);
  ASSERT_EQ(waitpid(gone, nullptr, 0), gone);
  const fs::path dead = dir / (".tmp." + std::to_string(gone) + ".model.msh");
  const fs::path alive = dir / (".tmp." + std::to_string(::getppid()) + ".model.msh");
  const fs::path other = dir / (".tmp." + std::to_string(gone) + ".other.msh");
  for (const auto& p : {dead, alive, other}) std::ofstream(p) << "half";
  pipeline::write_text_atomic((dir / "model.msh").string(), "whole");
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_TRUE(fs::exists(alive));  // another stage may be writing it now
  EXPECT_TRUE(fs::exists(other));  // another output's: left to its own next write
  EXPECT_EQ(pipeline::read_text((dir / "model.msh").string()), "whole");
  const std::string long_name = std::string(246, 'n') + ".json";
  const fs::path dead_long = dir / (".tmp." + std::to_string(gone) + ".json");  // its short form
  std::ofstream(dead_long) << "half";
  pipeline::write_text_atomic((dir / long_name).string(), "{}");
  EXPECT_EQ(pipeline::read_text((dir / long_name).string()), "{}");
  EXPECT_FALSE(fs::exists(dead_long));
}

TEST(write_atomic, failed_writer_leaves_no_file_and_keeps_old_one) {
  const fs::path dir = scratch_dir() / "atomic_fail";
  fs::remove_all(dir);
  const std::string path = (dir / "out.txt").string();
  EXPECT_THROW(pipeline::write_atomic(path, [](const std::string& tmp) {
                 pipeline::write_text_atomic(tmp, "half");
                 throw pipeline::algorithm_failed("x", "boom");
               }),
               pipeline::Error);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
  pipeline::write_text_atomic(path, "old");
  EXPECT_THROW(pipeline::write_atomic(path, [](const std::string&) { throw std::runtime_error("x"); }),
               std::runtime_error);
  EXPECT_EQ(pipeline::read_text(path), "old");
}

// A stage's outputs are written all or none: when a later write fails, the files the earlier ones
// wrote are removed (repair's mesh stayed when its report could not be written); an output not
// requested ("" path) is skipped.
TEST(write_all_or_none, a_failed_write_removes_the_ones_before_it) {
  const fs::path dir = scratch_dir() / "all_or_none";
  fs::remove_all(dir);
  const std::string a = (dir / "a.txt").string(), b = (dir / "b.txt").string(), c = (dir / "c.txt").string();
  bool skipped_ran = false;
  // the error names what it removed (generate_scan named only the failed file)
  EXPECT_EQ(error_message(pipeline::ErrorKind::io,
                          [&] {
                            pipeline::write_all_or_none({{a, [&] { pipeline::write_text_atomic(a, "a"); }},
                                                         {"", [&] { skipped_ran = true; }},
                                                         {b, [&] { pipeline::write_text_atomic(b, "b"); }},
                                                         {c, [&] { throw pipeline::io_failed(c, "disk full"); }}});
                          }),
            c + ": disk full (" + a + ", " + b + ", written before it, removed: a stage's outputs are all or none)");
  EXPECT_FALSE(skipped_ran);
  EXPECT_FALSE(fs::exists(a));
  EXPECT_FALSE(fs::exists(b));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
  pipeline::write_all_or_none({{a, [&] { pipeline::write_text_atomic(a, "a"); }}, {"", [] {}},
                               {b, [&] { pipeline::write_text_atomic(b, "b"); }}});
  EXPECT_EQ(pipeline::read_text(a) + pipeline::read_text(b), "ab");
  // a writer failing with another exception (a library's, std::bad_alloc) removes them too, and
  // the exception goes on unchanged (only pipeline errors were tested: sweep L)
  EXPECT_THROW(pipeline::write_all_or_none({{a, [&] { pipeline::write_text_atomic(a, "a"); }},
                                            {c, [] { throw std::runtime_error("gmsh: cannot write"); }}}),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(a));
  EXPECT_TRUE(fs::exists(b)) << "an output before the call is not the call's to remove";
}

// Outputs that cannot be written are found before the work, not after it: a folder that takes no
// new files (/proc, even for root), a "folder" that is a file, an output that is a folder, a link
// to a folder that is gone. A writable place passes without a trace: no probe file, no folder made.
TEST(require_writable_outputs, names_the_output_and_why_before_any_work) {
  const fs::path dir = scratch_dir() / "writable";
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto message = [](const std::string& path) {
    return error_message(pipeline::ErrorKind::io, [&] { pipeline::require_writable_outputs({"", path}); });
  };
  EXPECT_EQ(message((dir / "out.ply").string()), "no error");
  EXPECT_EQ(message((dir / "not" / "yet" / "out.ply").string()), "no error");
  EXPECT_FALSE(fs::exists(dir / "not"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
  EXPECT_EQ(message("/proc/x/out.ply").rfind("/proc/x/out.ply: cannot write in /proc: ", 0), 0u);
  pipeline::write_text_atomic((dir / "notes.txt").string(), "a file");
  const std::string under_file = (dir / "notes.txt" / "out.ply").string();
  EXPECT_EQ(message(under_file), under_file + ": cannot write in " + (dir / "notes.txt").string() + ": Not a directory");
  EXPECT_EQ(message(dir.string()), dir.string() + ": is a folder, not a file");
  fs::create_directory_symlink(dir / "nowhere", dir / "dangling");  // a link to a folder that is gone
  const std::string through_link = (dir / "dangling" / "out.ply").string();
  EXPECT_EQ(message(through_link), through_link + ": cannot write in " + (dir / "dangling").string() +
                                       ": No such file or directory");
}

// A full disk gave "cannot write mesh (format '.ply')" with no reason (fit, segment). Under a file
// size limit (SIGXFSZ ignored, so the write fails with EFBIG as a full disk fails with ENOSPC) each
// writer now gives the system's reason, and leaves neither the file nor its temporary.
TEST(write_atomic, a_write_the_system_refuses_gives_its_reason_and_no_file) {
  const fs::path dir = scratch_dir() / "limited";
  fs::create_directories(dir);
  pipeline::SurfaceMesh mesh;
  for (int i = 0; i < 500; ++i) {  // a strip of 1000 triangles, ~30 kB as binary PLY
    const auto a = mesh.add_vertex({double(i), 0, 0}), b = mesh.add_vertex({double(i), 1, 0}),
               c = mesh.add_vertex({i + 0.5, 0.5, 1}), d = mesh.add_vertex({i + 0.5, 0.5, -1});
    mesh.add_face(a, b, c);
    mesh.add_face(b, a, d);
  }
  pipeline::PointCloud cloud;
  cloud.points.assign(5000, pipeline::Point(1, 2, 3));
  const std::string text(20000, 'x');
  struct rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  struct rlimit low = old;
  low.rlim_cur = 4096;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &low), 0);
  std::vector<std::string> messages;
  for (const std::string name : {"m.ply", "m.off", "c.ply", "c.xyz", "t.json"}) {
    const std::string path = (dir / name).string();
    messages.push_back(error_message(pipeline::ErrorKind::io, [&] {
      if (name[0] == 'm') pipeline::write_surface_mesh(path, mesh);
      if (name[0] == 'c') pipeline::write_point_cloud(path, cloud);
      if (name[0] == 't') pipeline::write_text_atomic(path, text);
    }));
  }
  setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, old_handler);
  for (const auto& m : messages) EXPECT_NE(m.find(": File too large"), std::string::npos) << m;
  EXPECT_EQ(messages[0], (dir / "m.ply").string() + ": cannot write mesh (format '.ply'): File too large");
  EXPECT_TRUE(fs::is_empty(dir));  // no output, no temporary
}
