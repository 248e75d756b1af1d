// Interruption by a signal. SIGINT (Ctrl-C: the terminal sends it to the whole process group,
// gnuplot included), SIGTERM (kill, a batch system's time limit) and SIGHUP (a closed terminal)
// stop the program at once, whatever it is doing (reading, reducing, solving, writing, plotting):
//   1. the running child process (gnuplot) is killed and reaped (cli/child_process.h);
//   2. every temporary file and folder of this process is removed (io/atomic_file.h), so that
//      only complete files remain under result names;
//   3. one line on stderr says what was interrupted and what had been written completely:
//        stickslip: interrupted by SIGINT while plotting out/preload_80; complete: solve files
//        in out/preload_50, ...
//   4. the process exits with 128 + the signal number (130, 143, 129).
// The signal handler itself only writes the signal number to a pipe; a thread started by
// install_interruption_handling does the rest (so it may take locks and allocate), and ends the
// process with _exit while the other threads are wherever they are.
// SIGXFSZ (a file-size limit, `ulimit -f`) is ignored, so that such a write fails with EFBIG and is
// reported like a full disk instead of killing the program.
#pragma once

#include <string>

namespace stickslip {

// Call once, first thing in main.
void install_interruption_handling();

// What the line of an interruption says: the activity now running ("solving out/preload_80") and
// the results written completely so far, in order ("solve files in out/preload_50").
void interruption_doing(const std::string& activity);
void interruption_done(const std::string& result);

}  // namespace stickslip
