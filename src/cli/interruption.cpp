#include "cli/interruption.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

#include "cli/child_process.h"
#include "io/atomic_file.h"

namespace stickslip {
namespace {

int g_pipe[2] = {-1, -1};
std::mutex g_status_mutex;
std::string g_doing;
std::vector<std::string> g_done;

extern "C" void on_signal(int signal) {
  const int saved = errno;
  const int s = signal;
  (void)!::write(g_pipe[1], &s, sizeof s);
  errno = saved;
}

const char* signal_name(int s) {
  switch (s) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    case SIGHUP:
      return "SIGHUP";
    default:
      return "a signal";
  }
}

[[noreturn]] void stop(int signal) {
  kill_running_child();
  remove_all_temporaries_and_stop();
  std::string line = std::string("stickslip: interrupted by ") + signal_name(signal);
  {
    std::lock_guard<std::mutex> lock(g_status_mutex);
    line += " while " + (g_doing.empty() ? std::string("reading the input") : g_doing);
    if (g_done.empty()) {
      line += "; no result of this run was written completely";
    } else {
      line += "; complete: ";
      for (size_t i = 0; i < g_done.size(); ++i) line += (i ? ", " : "") + g_done[i];
      line += "; nothing else of this run";
    }
  }
  line += "\n";
  (void)!::write(2, line.data(), line.size());
  ::_exit(128 + signal);
}

void watch() {
  for (;;) {
    int s = 0;
    const ssize_t n = ::read(g_pipe[0], &s, sizeof s);
    if (n == static_cast<ssize_t>(sizeof s)) stop(s);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
  }
}

}  // namespace

void install_interruption_handling() {
  if (::pipe2(g_pipe, O_CLOEXEC) != 0) return;  // without it the default actions stay
  std::thread(watch).detach();
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  for (int s : {SIGINT, SIGTERM, SIGHUP}) {
    // A signal the caller set to be ignored stays ignored (`nohup`, background jobs of a
    // non-interactive shell).
    struct sigaction old {};
    if (::sigaction(s, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    ::sigaction(s, &action, nullptr);
  }
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  ::sigaction(SIGXFSZ, &ignore, nullptr);
}

void interruption_doing(const std::string& activity) {
  std::lock_guard<std::mutex> lock(g_status_mutex);
  g_doing = activity;
}

void interruption_done(const std::string& result) {
  std::lock_guard<std::mutex> lock(g_status_mutex);
  g_done.push_back(result);
}

}  // namespace stickslip
