// stickslip: the command-line program. Subcommands:
//   run     a case file through the whole pipeline (cli/pipeline.h).
//   reduce  Craig-Bampton reduction of the bodies of a case, to Harwell-Boeing files.
//   modes   modal analysis of the reference two-beam joint with stuck contact (issue 2).
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "core/errors.h"

#ifndef STICKSLIP_VERSION
#define STICKSLIP_VERSION "unknown"
#endif

int main(int argc, char** argv) {
  using namespace stickslip;
  CLI::App app{"stickslip: vibration and stresses of friction-damped structures"};
  app.set_version_flag("--version", std::string("stickslip ") + STICKSLIP_VERSION);
  app.require_subcommand(1);

  ModesCommand modes;
  CLI::App* modes_cmd = app.add_subcommand(
      "modes", "Modal analysis of the reference two-beam joint with stuck contact");
  modes_cmd->add_option("--arrangement", modes.arrangement, "butt or lap")
      ->check(CLI::IsMember({"butt", "lap"}))
      ->capture_default_str();
  modes_cmd->add_option("--modes", modes.num_modes, "number of lowest modes")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  modes_cmd->add_flag("--coarse", modes.thesis_coarse,
                      "the thesis's coarse mesh (240 nodes, 115 elements per beam)");
  modes_cmd->add_option("--element", modes.element, "hexahedron type: C3D8, C3D8I, C3D20, C3D20R")
      ->capture_default_str();
  modes_cmd->add_option("--kt", modes.k_t, "tangential contact stiffness per pair, N/m")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  modes_cmd->add_option("--kn", modes.k_n, "normal contact stiffness per pair, N/m")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  modes_cmd->add_option("-o,--output", modes.output_dir, "output folder")->capture_default_str();
  modes_cmd->add_flag("-q,--quiet", modes.quiet, "print nothing but errors");

  RunCommand run;
  CLI::App* run_cmd =
      app.add_subcommand("run", "Run a case file: reduction, harmonic balance, results");
  run_cmd->add_option("case", run.case_file, "case file (YAML, docs/case-file.md)")
      ->required()
      ->check(CLI::ExistingFile);
  run_cmd->add_option("-o,--output", run.output_dir,
                      "output folder (default: the case file's output.directory)");
  run_cmd->add_flag("-q,--quiet", run.quiet, "print nothing but errors");

  ReduceCommand reduce;
  CLI::App* reduce_cmd = app.add_subcommand(
      "reduce", "Craig-Bampton reduction of a case's mesh bodies, written as HBMAT-style files");
  reduce_cmd->add_option("case", reduce.case_file, "case file (YAML, docs/case-file.md)")
      ->required()
      ->check(CLI::ExistingFile);
  reduce_cmd->add_option("-o,--output", reduce.output_dir, "output folder")->capture_default_str();
  reduce_cmd->add_flag("-q,--quiet", reduce.quiet, "print nothing but errors");

  CLI11_PARSE(app, argc, argv);
  try {
    if (*modes_cmd) return run_modes(modes);
    if (*run_cmd) return run_case(run);
    if (*reduce_cmd) return run_reduce(reduce);
  } catch (const InvalidInput& e) {
    std::fprintf(stderr, "stickslip: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "stickslip: internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}
