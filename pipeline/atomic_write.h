#pragma once
/// Atomic output: every stage writes its outputs through these functions, so a failed or
/// interrupted stage never leaves a file that Make could mistake for a finished one.
#include <functional>
#include <string>
#include <vector>

namespace pipeline {

/// Calls writer(tmp_path) with a temporary path in the same directory as `path`, then
/// renames the temporary file to `path`. The parent directory is created if missing.
///
/// @param[in] path    final output path
/// @param[in] writer  writes the complete file to the path it is given; may throw
/// @throws Error(io) if the writer left no file or the rename failed; any exception of the
///         writer is re-thrown after the temporary file is removed. `path` is untouched on failure.
/// The temporary file is `.tmp.<pid>.<name>` (`.tmp.<pid><.ext>` for a name too long for that);
/// such files of `path` left by a process that no longer exists (killed by SIGKILL) are removed.
void write_atomic(const std::string& path, const std::function<void(const std::string& tmp_path)>& writer);

/// Makes SIGINT, SIGTERM and SIGHUP remove the temporary files write_atomic is writing before the
/// stage dies of them (exit status as before). Their default action had left `.tmp.<pid>.<name>`
/// beside the outputs: generate_scan killed while writing a 96 MB cloud. A signal that is ignored
/// or already handled is left alone. pipeline::run_main calls it for every stage.
void remove_temporary_files_on_signals();

/// One output of a stage for write_all_or_none: its path ("" = not requested, skipped) and the
/// call that writes it (atomically, e.g. write_surface_mesh).
struct Output {
  std::string path;
  std::function<void()> write;
};

/// Writes a stage's outputs all or none: runs the writes in order and, if one throws, removes
/// the files the earlier ones wrote before re-throwing, so Make never sees part of a failed
/// stage's outputs as new. (Each write is atomic on its own; this makes the set so.) A
/// pipeline::Error re-thrown names the files removed: an earlier copy at those paths is gone too.
/// SIGINT, SIGTERM and SIGHUP are held while the set is written and take effect after it.
void write_all_or_none(const std::vector<Output>& outputs);

/// The folder a file or folder at `path` would be made in: `path` itself if it is there, else the
/// nearest folder above it that is (write_atomic and solve make the missing ones); "." for a
/// relative path none of whose folders is there. Only missing folders are climbed past: anything
/// else in the way (no permission, a dangling link, a file) is returned, for the write to report.
std::string nearest_existing_folder(const std::string& path);

/// Checks, before any work, that each output can be written where its path says: its folder, or
/// the nearest folder above it that exists (write_atomic makes the rest), must take a new file.
/// A stage otherwise found out after its work (minutes of reconstruct or fit) that it could not
/// write there. The check creates and removes an empty file, so it holds for root, read-only
/// mounts and /proc alike. Empty paths (outputs not requested) are skipped.
/// @throws Error(io) "<path>: cannot write in <folder>: Permission denied", or "<path>: is a folder, not a file"
void require_writable_outputs(const std::vector<std::string>& paths);

/// Writes `text` to `path` atomically.
void write_text_atomic(const std::string& path, const std::string& text);

/// Why a write just failed, for its error line: the system's reason (errno: "No space left on
/// device", "File too large"), or "write error" if none was left. write_atomic clears errno before
/// its writer runs, so a reason is this write's own; call it at once, before errno changes.
std::string why_write_failed();

/// Reads a whole file into a string. @throws Error(bad_input) naming it if it is missing, a
/// directory, empty (require_file) or unreadable.
std::string read_text(const std::string& path);

}  // namespace pipeline
