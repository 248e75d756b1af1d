// stickslip: the command-line program (docs/command-line.md). Subcommands:
//   run      a case file through the whole pipeline.
//   mesh     the bodies' meshes as the case builds them.
//   modes    modes of the stuck assembly (of a case, or of the reference two-beam joint).
//   reduce   Craig-Bampton reduction of a case's mesh bodies, to Harwell-Boeing files.
//   solve    the harmonic balance, reusing reduce's files.
//   recover  full-model recovery from solve's files.
//   export   APDL macro / CalculiX deck of one solved point.
//   plot     the plots, from solve's files.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "cli/interruption.h"
#include "cli/processes.h"
#include "core/errors.h"
#include "core/printable.h"

#ifndef STICKSLIP_VERSION
#define STICKSLIP_VERSION "unknown"
#endif

namespace {

using namespace stickslip;

constexpr const char* kCaseHelp = "case file (YAML, docs/case-file.md)";
constexpr const char* kOutputHelp = "output folder (default: the case file's output.directory)";

CLI::App* add_stage(CLI::App& app, const std::string& name, const std::string& description,
                    StageCommand& stage) {
  CLI::App* cmd = app.add_subcommand(name, description);
  cmd->add_option("case", stage.case_file, kCaseHelp)->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", stage.output_dir, kOutputHelp);
  cmd->add_flag("-q,--quiet", stage.quiet, "print nothing but errors");
  return cmd;
}

}  // namespace

int main(int argc, char** argv) {
  install_interruption_handling();  // SIGINT, SIGTERM, SIGHUP: exit 128 + signal, nothing partial
  CLI::App app{
      "stickslip: vibration and stresses of friction-damped structures.\n"
      "`stickslip run CASE` runs everything; the other subcommands run one stage and reuse the "
      "files of earlier stages in the output folder (docs/command-line.md).",
      "stickslip"};
  app.set_version_flag("--version", std::string("stickslip ") + STICKSLIP_VERSION);
  app.require_subcommand(1);

  StageCommand run;
  CLI::App* run_cmd =
      add_stage(app, "run",
                "Run a case file: reduction, harmonic balance, recovery, plots (all stages)", run);

  StageCommand mesh;
  CLI::App* mesh_cmd = add_stage(
      app, "mesh", "Write the bodies' meshes as the case builds them: DIR/mesh/<body>.inp, .vtu",
      mesh);

  ModesCommand modes;
  CLI::App* modes_cmd = app.add_subcommand(
      "modes",
      "Modes of the stuck assembly: of a case's reduced model (DIR/modes/), or without a case "
      "of the reference two-beam joint's full model");
  modes_cmd->add_option("case", modes.case_file, "case file (optional)")->check(CLI::ExistingFile);
  modes_cmd->add_option("--modes", modes.num_modes, "number of lowest modes")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  CLI::Option* arrangement =
      modes_cmd->add_option("--arrangement", modes.arrangement, "without a case: butt or lap")
          ->check(CLI::IsMember({"butt", "lap"}))
          ->capture_default_str();
  CLI::Option* coarse =
      modes_cmd->add_flag("--coarse", modes.thesis_coarse,
                          "without a case: the thesis's coarse mesh (240 nodes, 115 elements "
                          "per beam)");
  CLI::Option* element =
      modes_cmd
          ->add_option("--element", modes.element,
                       "without a case: hexahedron type C3D8, C3D8I, C3D20, C3D20R")
          ->capture_default_str();
  CLI::Option* kt =
      modes_cmd->add_option("--kt", modes.k_t, "without a case: tangential stiffness per pair, N/m")
          ->check(CLI::PositiveNumber)
          ->capture_default_str();
  CLI::Option* kn =
      modes_cmd->add_option("--kn", modes.k_n, "without a case: normal stiffness per pair, N/m")
          ->check(CLI::PositiveNumber)
          ->capture_default_str();
  modes_cmd->add_option("-o,--output", modes.output_dir,
                        "output folder (default: the case's output.directory, or . without a "
                        "case)");
  modes_cmd->add_flag("-q,--quiet", modes.quiet, "print nothing but errors");

  ReduceCommand reduce;
  CLI::App* reduce_cmd = add_stage(
      app, "reduce",
      "Craig-Bampton reduction of the case's mesh bodies: DIR/reduced/ (HBMAT-style files and "
      "a manifest that solve, recover, export and modes check before reusing them)",
      reduce.stage);
  reduce_cmd->add_flag("--basis", reduce.basis,
                       "also write the Craig-Bampton basis T (<body>_T.bin: full DOFs x reduced "
                       "DOFs) for the mode shapes of `modes CASE`; written anyway with "
                       "recovery.method: expansion");

  StageCommand solve;
  CLI::App* solve_cmd =
      add_stage(app, "solve",
                "Harmonic balance: points.csv, master_response.csv, contact_forces.csv, "
                "contact_state.csv, histories.csv, summary.json (reuses DIR/reduced/ when fresh)",
                solve);

  RecoverCommand recover;
  CLI::App* recover_cmd =
      add_stage(app, "recover", "Full-model recovery of solved points, from the solve files in DIR",
                recover.stage);
  recover_cmd->add_option(
      "--point", recover.point,
      "peak, all, a point number of points.csv or a comma-separated list (default: the case's "
      "recovery.points)");

  ExportCommand export_;
  CLI::App* export_cmd = add_stage(
      app, "export",
      "The loads of one solved point on the full bodies as an ANSYS APDL macro or a CalculiX "
      "deck, from the solve files in DIR",
      export_.stage);
  export_cmd
      ->add_option("--point", export_.points,
                   "point number of points.csv, a comma-separated list of them, peak or all")
      ->required();
  export_cmd->add_option("--format", export_.format, "apdl or calculix")
      ->required()
      ->check(CLI::IsMember({"apdl", "calculix"}));

  PlotCommand plot;
  CLI::App* plot_cmd = app.add_subcommand(
      "plot", "(Re)render the plots (PNG, SVG with gnuplot) from the CSV files in DIR");
  plot_cmd->add_option("dir", plot.dir, "output folder of a solve")->required();
  plot_cmd->add_flag("-q,--quiet", plot.quiet, "print nothing but errors");
  plot_cmd->add_flag("--log", plot.log,
                     "amplitude (FRF) plots on a logarithmic axis (default: as the run drew them, "
                     "output.log_amplitude)");

  KeysCommand keys;
  CLI::App* keys_cmd = app.add_subcommand(
      "keys", "List the case file's keys: type, unit, default, study-able, one line of help");
  keys_cmd->add_option("section", keys.section,
                       "only the keys of this section or key (e.g. analysis, contacts[])");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);  // --help: usage on stdout, exit 0
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    if (argc > 1 && argv[1][0] != '-' && app.get_subcommands({}).size() > 0) {
      bool known = false;
      std::string names;
      for (const CLI::App* sub : app.get_subcommands({})) {
        known = known || sub->get_name() == argv[1];
        names += (names.empty() ? "" : ", ") + sub->get_name();
      }
      if (!known) {
        std::fprintf(stderr, "stickslip: error: unknown subcommand '%s' (one of %s; stickslip "
                     "--help)\n", printable(argv[1]).c_str(), names.c_str());
        return 2;
      }
    }
    // A usage error (missing case file, unknown or missing subcommand or option) is bad input:
    // exit 2 with the one error format of the program (CLI11's own codes 105-109 otherwise).
    std::fprintf(stderr, "stickslip: error: %s (stickslip --help, docs/command-line.md)\n",
                 e.what());
    return 2;
  }
  const auto run_command = [&]() -> int {
    if (*run_cmd) return run_case(run);
    if (*mesh_cmd) return run_mesh(mesh);
    if (*modes_cmd) {
      if (!modes.case_file.empty()) {
        for (const CLI::Option* o : {arrangement, coarse, element, kt, kn}) {
          if (o->count() > 0) {
            throw InvalidInput({"", 0, o->get_name()},
                               "only for the reference joint (modes without a case file)");
          }
        }
      }
      return run_modes(modes);
    }
    if (*reduce_cmd) return run_reduce(reduce);
    if (*solve_cmd) return run_solve(solve);
    if (*recover_cmd) return run_recover(recover);
    if (*export_cmd) return run_export(export_);
    if (*plot_cmd) return run_plot(plot);
    if (*keys_cmd) return run_keys(keys);
    return 0;
  };
  // Under mpirun with several processes (cli/processes.h): `run` spreads its work over them;
  // any other command would run P times over the same files.
  if (launcher_world_size() > 1) {
    const bool speaker = launcher_rank() == 0;  // the others say nothing
    if (!*run_cmd) {
      if (speaker) {
        std::fprintf(stderr,
                     "stickslip: error: only `stickslip run` spreads its work over several "
                     "processes; run `stickslip %s` without mpirun (docs/command-line.md)\n",
                     app.get_subcommands().front()->get_name().c_str());
      }
      return 2;
    }
    try {
      start_processes();
    } catch (const MpiUnavailable& e) {
      if (speaker) std::fprintf(stderr, "stickslip: error: %s\n", e.what());
      return 5;
    }
  }
  int code = 0;
  try {
    code = run_command();
  } catch (const PeerStopped&) {
    code = 0;  // a rank other than 0: rank 0 reports the error
  } catch (...) {
    const std::string text = describe_failure(std::current_exception(), &code);
    if (processes() == nullptr || processes()->root()) std::fprintf(stderr, "%s\n", text.c_str());
  }
  if (processes() != nullptr) processes()->finish();
  return code;
}
