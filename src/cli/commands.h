// The subcommands of the stickslip program. Each returns the process exit code
// (0 success, 1 numerical failure reported to the user); bad input throws InvalidInput.
#pragma once

#include <string>

namespace stickslip {

struct ModesCommand {
  std::string arrangement = "butt";
  int num_modes = 8;
  bool thesis_coarse = false;
  std::string element = "C3D8I";
  double k_t = 4.467e9;   // N/m per pair (the thesis)
  double k_n = 5.6309e9;  // N/m per pair (the thesis)
  std::string output_dir = ".";
  bool quiet = false;
};
int run_modes(const ModesCommand& command);

struct RunCommand {
  std::string case_file;
  std::string output_dir;  // empty: the case file's output.directory
  bool quiet = false;
};
// Exit code 1 when some frequency points did not converge (they are still written).
int run_case(const RunCommand& command);

}  // namespace stickslip

namespace stickslip {

struct ReduceCommand {
  std::string case_file;
  std::string output_dir = ".";
  bool quiet = false;
};
// Reduces every mesh body of the case (Craig–Bampton onto its master nodes, as `run` would) and
// writes <body>_K.hb, <body>_M.hb (Harwell–Boeing RSA, as ANSYS HBMAT) with their .mapping files.
int run_reduce(const ReduceCommand& command);

}  // namespace stickslip
