// The processes of one `mpirun -n P stickslip run CASE` (docs/command-line.md, "Several
// processes"). MPI itself is in a plugin (cli/mpi_plugin_api.h, libstickslip_mpi.so) loaded only
// when the launcher's environment says that P > 1 processes were started (OMPI_COMM_WORLD_SIZE of
// Open MPI, PMI_SIZE of MPICH and Slurm); a program started alone never loads it.
//
// Where the plugin is looked for, in this order (the first that loads wins):
//   1. the environment variable STICKSLIP_MPI_PLUGIN, when set (then only there);
//   2. libstickslip_mpi.so beside the program, then in ../lib/stickslip/ from there;
//   3. the plugin of the build tree this code was built in.
// When none loads, start_processes() throws MpiUnavailable listing each path and dlopen's reason.
//
// Errors: a failed MPI operation throws std::runtime_error ("MPI: ..."). The failure of one
// process is made known to all of them by checkpoint() (a collective) or by a message of the
// protocol of cli/distributed_run.h; the error is printed once, by rank 0 (describe_failure).
#pragma once

#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

namespace stickslip {

// The number of processes the launcher started and this one's rank in them, from the
// environment (1 and 0 when none).
int launcher_world_size();
int launcher_rank();

// The plugin could not be loaded or MPI not initialised (the installation, not the input).
class MpiUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An error of another process, already worded as the program prints it ("stickslip: error:
// ..."), with its exit code: thrown on rank 0, which prints it.
class PeerError : public std::runtime_error {
 public:
  PeerError(const std::string& text, int exit_code)
      : std::runtime_error(text), exit_code_(exit_code) {}
  int exit_code() const { return exit_code_; }

 private:
  int exit_code_;
};

// Thrown on a rank other than 0 when the run stops because of an error that rank 0 reports.
class PeerStopped : public std::runtime_error {
 public:
  PeerStopped() : std::runtime_error("stopped: another process failed") {}
};

// The line the program prints for an exception escaping a command, and its exit code: bad input
// (InvalidInput, a file-system refusal) 2, a missing plugin (Gmsh, MPI) 5, anything else 3
// ("internal error"); a PeerError as it is.
std::string describe_failure(std::exception_ptr error, int* exit_code);

class Processes {
 public:
  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }

  struct Message {
    int from = 0;
    int tag = 0;
    std::string bytes;
  };
  // Returns at once; the bytes are copied.
  void send(int dest, int tag, const std::string& bytes);
  // Waits for the next message from `source` (-1: any).
  Message receive(int source = -1);
  // Whether a message from `source` can be received now.
  bool pending(int source);
  // Lets sends under way advance (call now and then during long work). Never throws.
  void progress() noexcept;

  // Collective: every process calls it with its own error (null: none). Returns when no
  // process failed. Otherwise the lowest failing rank's error is reported: rank 0 throws it (its
  // own, or a PeerError with the other rank's words), every other rank throws PeerStopped.
  void checkpoint(std::exception_ptr error);

  // Completes the sends and finalizes MPI (once; later calls do nothing).
  void finish() noexcept;
  // The last resort when a peer cannot be stopped otherwise.
  [[noreturn]] void abort(int code) noexcept;

 private:
  friend Processes& start_processes();
  Processes() = default;
  int rank_ = 0, size_ = 1;
  bool finished_ = false;
};

// Loads the plugin and initialises MPI (once); throws MpiUnavailable.
Processes& start_processes();
// The processes started by start_processes(), or null: the program runs alone.
Processes* processes();

// Byte buffers of the messages (same byte order on every process: the processes of one run are
// the same program on one kind of machine).
class Packer {
 public:
  void put(std::int64_t v) { raw(&v, sizeof v); }
  void put(double v) { raw(&v, sizeof v); }
  void put(const std::string& s) {
    put(static_cast<std::int64_t>(s.size()));
    bytes_ += s;
  }
  void put(const std::vector<double>& v) {
    put(static_cast<std::int64_t>(v.size()));
    raw(v.data(), v.size() * sizeof(double));
  }
  const std::string& bytes() const { return bytes_; }
  std::string take() { return std::move(bytes_); }

 private:
  void raw(const void* p, size_t n) { bytes_.append(static_cast<const char*>(p), n); }
  std::string bytes_;
};

// Reads what a Packer wrote, in the same order; std::runtime_error when the bytes end early.
class Unpacker {
 public:
  explicit Unpacker(const std::string& bytes) : bytes_(bytes) {}
  std::int64_t integer();
  double number();
  std::string text();
  std::vector<double> numbers();
  bool done() const { return at_ == bytes_.size(); }

 private:
  void raw(void* p, size_t n);
  const std::string& bytes_;
  size_t at_ = 0;
};

}  // namespace stickslip
