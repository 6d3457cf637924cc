#include "pipeline/atomic_write.h"

#include <unistd.h>

#include <cerrno>
#include <csignal>
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

namespace {
// The temporary files being written, for the signal handler below to remove. Plain arrays and a
// sig_atomic_t flag per slot: all a handler may touch. A slot's path is written before its flag
// is set, and the flag cleared before the slot is reused.
constexpr int kPendingSlots = 8;
char pending_path[kPendingSlots][4096];
volatile std::sig_atomic_t pending_used[kPendingSlots];
// While write_all_or_none renames a stage's outputs into place, a signal is held until the set is
// complete (write_all_or_none raises it again then): the signal mask below holds it on the writing
// thread, this flag on any other (an OpenMP worker may be the one the kernel picks).
volatile std::sig_atomic_t writing_set = 0, held_signal = 0;

extern "C" void remove_pending_and_reraise(int sig) {
  if (writing_set) {
    held_signal = sig;
    return;
  }
  for (int k = 0; k < kPendingSlots; ++k)
    if (pending_used[k]) ::unlink(pending_path[k]);
  std::signal(sig, SIG_DFL);  // then die of the signal as before, so the caller sees it
  ::raise(sig);
}

// Holds a temporary file in a slot while it is written (none free, or a path too long: not held,
// as before this existed).
struct PendingFile {
  int slot = -1;
  explicit PendingFile(const std::string& tmp) {
    if (tmp.size() >= sizeof pending_path[0]) return;
    for (int k = 0; k < kPendingSlots && slot < 0; ++k)
      if (!pending_used[k]) {
        std::memcpy(pending_path[k], tmp.c_str(), tmp.size() + 1);
        pending_used[k] = 1;
        slot = k;
      }
  }
  ~PendingFile() {
    if (slot >= 0) pending_used[slot] = 0;
  }
};
}  // namespace

void remove_temporary_files_on_signals() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    sigaction(sig, nullptr, &old);
    if (old.sa_handler != SIG_DFL) continue;  // ignored (nohup, `&` in a script) or handled: left so
    struct sigaction a {};
    a.sa_handler = remove_pending_and_reraise;
    sigemptyset(&a.sa_mask);
    sigaction(sig, &a, nullptr);
  }
}

// Removes `.tmp.<pid>.<name>` beside `target` whose process is gone: a stage killed by SIGKILL
// (which no handler sees) left its temporary file, a model's size, for good (sweep P). Only this
// output's own name is looked for, and only a process that no longer exists (kill(pid, 0) fails
// with ESRCH) counts as gone, so a stage writing the same output at this moment keeps its file.
namespace {
// The temporary file's name for `target` written by process `pid`: `.tmp.<pid>.<name>`, the
// extension last (some writers, gmsh and CGAL, choose the format from it). A name too long for
// the prefix (a legal 245-255 character name was refused, sweep P) keeps only its extension.
std::string temporary_name(const std::string& pid, const fs::path& target) {
  const std::string prefix = ".tmp." + pid + ".", name = target.filename().string();
  return prefix.size() + name.size() <= 255 ? prefix + name : ".tmp." + pid + target.extension().string();
}

void remove_stale_temporaries(const fs::path& target) {
  std::error_code ec;
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string f = entry.path().filename().string();
    if (f.rfind(".tmp.", 0) != 0) continue;
    const std::string pid_text = f.substr(5, f.find_first_not_of("0123456789", 5) - 5);
    if (pid_text.empty() || pid_text.size() > 9 || f != temporary_name(pid_text, target)) continue;
    const pid_t pid = pid_t(std::stol(pid_text));
    if (pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH) fs::remove(entry.path(), ec);
  }
}
}  // namespace

void write_atomic(const std::string& path, const std::function<void(const std::string&)>& writer) {
  const fs::path target(path);
  if (target.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(target.parent_path(), ec);
    if (ec) throw io_failed(path, "cannot create directory: " + ec.message());
  }
  remove_stale_temporaries(target);
  const std::string tmp = (target.parent_path() / temporary_name(std::to_string(::getpid()), target)).string();
  const PendingFile pending(tmp);
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
  // Ctrl-C, SIGTERM and SIGHUP wait until the set is written (or removed): one between two
  // outputs left the new first ones beside the earlier run's others, a set no run made (sweep P).
  // A write that hangs can still be killed (SIGKILL).
  sigset_t stop_signals, before;
  sigemptyset(&stop_signals);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&stop_signals, sig);
  pthread_sigmask(SIG_BLOCK, &stop_signals, &before);
  writing_set = 1;
  struct Unblock {
    sigset_t mask;
    ~Unblock() {
      writing_set = 0;
      pthread_sigmask(SIG_SETMASK, &mask, nullptr);
      if (const int sig = held_signal) held_signal = 0, ::raise(sig);
    }
  } unblock{before};
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
