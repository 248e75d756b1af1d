// `stickslip plot DIR`: (re)renders the plots of a solve from the files in DIR (or in each study
// folder DIR/<parameter>_<value>/, plus the overlay frf_study), and frf_full_vs_reduced from the
// data file the recovery left (the recovered full-model amplitudes are in no CSV). Every script is
// written again by stickslip (cli/plots.h): no script found in DIR is run. Exit status
// kExitPlotsMissing when pictures could not be drawn.
#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include <fmt/core.h>

#include "cli/commands.h"
#include "cli/interruption.h"
#include "cli/plots.h"
#include "cli/progress.h"
#include "cli/results_files.h"
#include "core/errors.h"

namespace stickslip {

int run_plot(const PlotCommand& command) {
  namespace fs = std::filesystem;
  const fs::path dir(command.dir);
  const auto say = stderr_progress(command.quiet);
  const std::string hint = "stickslip solve CASE -o " + dir.string();
  if (!fs::is_directory(dir)) {
    throw InvalidInput({dir.string(), 0, ""}, "no such folder: run `" + hint + "` first");
  }
  PlotLog plots;
  const auto plot_folder = [&](const fs::path& folder, const SolveResults& results,
                               const std::string& prefix) {
    const std::vector<PlotSeries> frf = frf_series(results, prefix);
    const PlotOptions options{command.log || results.log_amplitude};
    interruption_doing("plotting in " + folder.string());
    plot_solve_results(folder, results, frf, &plots, options);
    redraw_full_vs_reduced(folder, results.title, &plots, options);
    interruption_done("plots in " + folder.string());
    say("plots in " + folder.string());
    return std::make_pair(results.title, frf);
  };
  if (fs::exists(dir / "points.csv")) {
    plot_folder(dir, read_solve_results(dir, hint), "");
    return plots_exit_code(plots, dir);
  }
  // A study: every sub-folder with solve files, in the order of the studied value (summary.json's
  // study value; the folder name's suffix for folders written before it was recorded).
  struct StudyFolder {
    double value;
    fs::path folder;
    SolveResults results;
  };
  std::vector<StudyFolder> folders;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    if (!e.is_directory() || !fs::exists(e.path() / "points.csv")) continue;
    SolveResults results = read_solve_results(e.path(), hint);
    const std::string name = e.path().filename().string();
    const size_t underscore = name.rfind('_');
    const double value = !results.study_parameter.empty() ? results.study_value
                         : underscore == std::string::npos
                             ? 0.0
                             : std::atof(name.c_str() + underscore + 1);
    folders.push_back({value, e.path(), std::move(results)});
  }
  if (folders.empty()) require_stage_file(dir / "points.csv", hint);
  std::stable_sort(folders.begin(), folders.end(),
                   [](const StudyFolder& a, const StudyFolder& b) { return a.value < b.value; });
  std::vector<std::vector<PlotSeries>> overlay;
  std::string title, parameter;
  bool log_amplitude = command.log;
  for (const StudyFolder& f : folders) {
    log_amplitude |= f.results.log_amplitude;
    const std::string name = f.folder.filename().string();
    auto [folder_title, frf] = plot_folder(f.folder, f.results, name + ": ");
    title = folder_title;
    parameter = !f.results.study_parameter.empty() ? f.results.study_parameter
                                                   : name.substr(0, name.rfind('_'));
    overlay.push_back(frf);
  }
  if (folders.size() > 1) {
    interruption_doing("plotting the study overlay in " + dir.string());
    plot_study(dir, title, parameter, overlay, &plots, PlotOptions{log_amplitude});
  }
  return plots_exit_code(plots, dir);
}

}  // namespace stickslip
