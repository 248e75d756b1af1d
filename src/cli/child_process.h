// Running another program (gnuplot) without a shell: fork and execv with an argument vector, the
// working directory set in the child, stdin and stdout on /dev/null, stderr captured. No text of
// ours or of the user's is ever interpreted by a shell.
//
// At most one child runs at a time (the main thread runs them one after another). While it runs,
// its process id is registered so that an interruption (cli/interruption.h) can kill and reap it
// before removing the temporaries it might be writing: kill_running_child().
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace stickslip {

// The executable `name` on $PATH (as a shell would find it), or empty if there is none.
std::filesystem::path find_program(const std::string& name);

struct ChildOutcome {
  bool started = false;   // false: fork or exec failed (message says why)
  bool exited = false;    // ended by exit(), with exit_code
  int exit_code = -1;
  int signal = 0;         // ended by this signal (exited false)
  std::string message;    // the last lines of the child's stderr, or why it did not start
  bool succeeded() const { return started && exited && exit_code == 0; }
};

// Runs `program` (a path) with arguments `args` (argv[1..]) in `working_dir`; waits for it.
// `inherit_fd` (>= 0): a close-on-exec descriptor the program keeps open all the same (the lock of
// the TemporaryFolder it writes into, io/atomic_file.h).
ChildOutcome run_program(const std::filesystem::path& program, const std::vector<std::string>& args,
                         const std::filesystem::path& working_dir, int inherit_fd = -1);

// For the interruption handler (another thread): sends SIGKILL to the running child, if any, and
// reaps it; afterwards no child is started any more (run_program blocks). Call once, then exit.
void kill_running_child();

}  // namespace stickslip
