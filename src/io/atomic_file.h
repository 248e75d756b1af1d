// Atomic file output and the temporaries behind it.
//
// write_file_atomically: the content is written to a temporary file in a private folder of this
// process inside the target's directory (TemporaryFolder: same file system, so the final POSIX
// rename is atomic) and renamed onto `path` only once it is complete, flushed and closed: a
// reader never sees a half-written result and an existing file is replaced in one step. If
// `write` throws, or a write fails, the temporary is removed and `path` is left as it was.
//
// Temporaries and how leftovers are recognised. A TemporaryFolder of directory DIR is
//   DIR/.stickslip-tmp-<pid>-<random>/        the temporaries (hidden: no glob of results sees it)
//   DIR/.stickslip-tmp-<pid>-<random>.lock    held with flock(LOCK_EX) while the folder lives
// The lock file is created and locked before the folder and removed after it. The kernel releases
// the lock when its holder dies, however it dies (SIGKILL included), and a child process that
// writes into the folder (gnuplot) holds it too (it inherits the descriptor). So a folder is
// "written by no live process" exactly when its lock file can be locked: the first TemporaryFolder
// a process makes in a directory first removes every such folder there (remove_stale_temporaries),
// and the files `<name>.tmp.<pid>.<n>` of older versions of stickslip whose process no longer
// exists. Process ids play no part in the decision for folders (they may be reused, or belong to
// another host sharing the folder over NFS, where flock is carried by NFS locks).
//
// Errors (cannot create the temporary, write failure, rename failure) throw InvalidInput with
// SourceLocation{path} and the reason in words (strerror: "No space left on device",
// "Read-only file system", "File name too long", ...). Exceptions thrown by `write` propagate.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace stickslip {

// Writes the file by calling write(stream); the stream is binary (no newline translation) and
// uses the classic "C" locale.
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write);

// Moves the complete file `from` (normally in a TemporaryFolder of the same directory) onto `to`
// in one step; InvalidInput naming `to` and the reason if the file system refuses.
void publish_file(const std::filesystem::path& from, const std::filesystem::path& to);

// The files this process has published (publish_file, write_file_atomically) under `dir` or its
// subfolders, relative to `dir`, in the order they were first published (summary.json's `files`,
// and what a run keeps when it removes the files of an earlier run).
std::vector<std::filesystem::path> published_files_under(const std::filesystem::path& dir);

class TemporaryFolder {
 public:
  // Creates the folder and its lock in `dir` (which must exist). InvalidInput naming `dir` and
  // the reason when the directory cannot be written.
  explicit TemporaryFolder(const std::filesystem::path& dir);
  ~TemporaryFolder();  // removes the folder, its content and the lock file
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }
  // The open descriptor of the lock file (close-on-exec): a child process that writes into the
  // folder should inherit it, so that the folder counts as live while the child lives.
  int lock_descriptor() const { return lock_fd_; }
  // Creates the new empty file path()/name for writing; returns its descriptor (the caller
  // closes it). InvalidInput naming `display_path` and the reason on failure.
  int create_file(const std::string& name, const std::string& display_path) const;

 private:
  std::filesystem::path path_, lock_path_;
  int lock_fd_ = -1;
};

// Removes from `dir` the temporaries of processes that are gone (see above); returns how many
// folders and files it removed. Errors are ignored (a leftover stays for the next time).
int remove_stale_temporaries(const std::filesystem::path& dir);

// For the interruption handler (another thread), just before the process exits: removes every
// TemporaryFolder of this process; afterwards no temporary file can be created any more (the
// calls block). Call once.
void remove_all_temporaries_and_stop();

// Files that results must never replace (the inputs of a case, when the output folder is theirs):
// publish_file (hence write_file_atomically) refuses a target that is the same file (device and
// inode) as one of them, with InvalidInput naming it, and the clean-up of temporaries never
// removes one. Paths that do not exist (or are empty) are ignored.
void protect_input_file(const std::filesystem::path& path);

// Creates `dir` and its missing parents. InvalidInput naming the path and the reason in words
// when that is impossible: a read-only file system, no permission, a name too long, `dir` or one
// of its parents an existing file.
void create_output_folder(const std::filesystem::path& dir);

}  // namespace stickslip
