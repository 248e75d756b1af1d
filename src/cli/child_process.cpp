#include "cli/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <mutex>

namespace stickslip {
namespace {

// Guards g_child: run_program holds it while forking and while unregistering the child (before
// reaping it, so that the id cannot belong to another process while it is registered);
// kill_running_child takes it for good.
std::mutex g_child_mutex;
pid_t g_child = 0;

// The last kKeep characters of the child's stderr are kept for the message.
constexpr size_t kKeep = 2000;

// In the child, between fork and exec: only async-signal-safe calls.
[[noreturn]] void child_fail(const char* what) {
  const char* reason = std::strerror(errno);  // not async-signal-safe in theory; the text is static
  (void)!::write(2, what, std::strlen(what));
  (void)!::write(2, ": ", 2);
  (void)!::write(2, reason, std::strlen(reason));
  (void)!::write(2, "\n", 1);
  ::_exit(127);
}

std::string tail_lines(const std::string& text) {
  std::string s = text;
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  // The last three lines at most.
  size_t at = s.size();
  for (int lines = 0; lines < 3 && at != std::string::npos && at > 0; ++lines) {
    at = s.rfind('\n', at - 1);
  }
  if (at != std::string::npos && at < s.size()) s = s.substr(at + 1);
  for (char& c : s) {
    if (c == '\n') c = ' ';
  }
  return s;
}

}  // namespace

std::filesystem::path find_program(const std::string& name) {
  const char* path = std::getenv("PATH");
  const std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  size_t begin = 0;
  while (begin <= dirs.size()) {
    size_t end = dirs.find(':', begin);
    if (end == std::string::npos) end = dirs.size();
    const std::string dir = end > begin ? dirs.substr(begin, end - begin) : ".";
    const std::filesystem::path candidate = std::filesystem::path(dir) / name;
    struct stat st {};
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
        ::access(candidate.c_str(), X_OK) == 0) {
      return candidate;
    }
    begin = end + 1;
  }
  return {};
}

ChildOutcome run_program(const std::filesystem::path& program, const std::vector<std::string>& args,
                         const std::filesystem::path& working_dir, int inherit_fd) {
  ChildOutcome outcome;
  // Everything the child needs is prepared before fork (no allocation after it).
  const std::string program_path = program.string();
  const std::string cwd = working_dir.empty() ? "." : working_dir.string();
  std::vector<std::string> storage;
  storage.push_back(program.filename().string());
  storage.insert(storage.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& s : storage) argv.push_back(s.data());
  argv.push_back(nullptr);

  int err_pipe[2];
  if (::pipe2(err_pipe, O_CLOEXEC) != 0) {
    outcome.message = std::string("cannot create a pipe: ") + std::strerror(errno);
    return outcome;
  }
  pid_t pid;
  {
    std::lock_guard<std::mutex> lock(g_child_mutex);
    pid = ::fork();
    if (pid == 0) {
      // Child: default signal dispositions and an empty mask (the parent's handlers are not ours
      // to run), stdin/stdout on /dev/null, stderr into the pipe, then the program.
      struct sigaction dfl {};
      dfl.sa_handler = SIG_DFL;
      for (int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) ::sigaction(s, &dfl, nullptr);
      sigset_t none;
      sigemptyset(&none);
      ::sigprocmask(SIG_SETMASK, &none, nullptr);
      const int null = ::open("/dev/null", O_RDWR);
      if (null < 0 || ::dup2(null, 0) < 0 || ::dup2(null, 1) < 0 || ::dup2(err_pipe[1], 2) < 0) {
        ::_exit(127);
      }
      if (inherit_fd >= 0) ::fcntl(inherit_fd, F_SETFD, 0);
      if (::chdir(cwd.c_str()) != 0) child_fail("cannot enter the working folder");
      ::execv(program_path.c_str(), argv.data());
      child_fail("cannot run the program");
    }
    if (pid > 0) g_child = pid;
  }
  ::close(err_pipe[1]);
  if (pid < 0) {
    outcome.message = std::string("cannot start a process: ") + std::strerror(errno);
    ::close(err_pipe[0]);
    return outcome;
  }
  outcome.started = true;
  std::string err;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(err_pipe[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    err.append(buffer, static_cast<size_t>(n));
    if (err.size() > 2 * kKeep) err.erase(0, err.size() - kKeep);
  }
  ::close(err_pipe[0]);
  // Wait without reaping, unregister, then reap: while registered the id is still ours.
  siginfo_t info{};
  while (::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOWAIT) != 0 && errno == EINTR) {
  }
  {
    std::lock_guard<std::mutex> lock(g_child_mutex);
    g_child = 0;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status)) {
    outcome.exited = true;
    outcome.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    outcome.signal = WTERMSIG(status);
  }
  outcome.message = tail_lines(err);
  if (outcome.exited && outcome.exit_code == 127 && outcome.message.empty()) {
    outcome.message = "could not be started";
  }
  return outcome;
}

void kill_running_child() {
  g_child_mutex.lock();  // never unlocked: no child starts after this
  if (g_child > 0) {
    ::kill(g_child, SIGKILL);
    int status;
    while (::waitpid(g_child, &status, 0) < 0 && errno == EINTR) {
    }
    g_child = 0;
  }
}

}  // namespace stickslip
