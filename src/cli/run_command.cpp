// `stickslip run CASE.yaml`: the case file through the pipeline (cli/pipeline.h), results written
// as tidy CSV plus summary.json (docs/output-files.md). Every file is written atomically.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include <fmt/core.h>
#include <fmt/ostream.h>

#include "cli/commands.h"
#include "cli/pipeline.h"
#include "cli/plots.h"
#include "cli/recovery_stage.h"
#include "core/errors.h"
#include "core/types.h"
#include "io/atomic_file.h"
#include "io/case_file.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

const char* kLocalAxes[3] = {"t1", "t2", "n"};
const char* kGlobalAxes[3] = {"x", "y", "z"};

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          out += fmt::format("\\u{:04x}", static_cast<int>(c));
        } else {
          out += c;
        }
    }
  }
  return out;
}

double total_dissipation(const FrequencyPoint& p) {
  double e = 0;
  for (const PairResponse& r : p.pairs) e += r.cycle.dissipated_energy;
  return e;
}

// Name of the contact pair's axis rows: 3D contacts t1, t2, n; 1D laws "u".
std::string local_axis(const PreparedModel& model, int pair, int row) {
  return model.pairs[pair].frame.rows() == 3 ? kLocalAxes[row] : "u";
}

void write_results(const fs::path& dir, const CaseDefinition& def, const PreparedModel& model,
                   const SolvedCase& solved, double seconds_total) {
  fs::create_directories(dir);
  const FrequencyResponse& fr = solved.response;
  const std::vector<int>& harmonics = fr.harmonics;

  write_file_atomically((dir / "points.csv").string(), [&](std::ostream& out) {
    out << "point,frequency_hz,converged,iterations,residual,dissipated_energy,residual_relative\n";
    for (size_t i = 0; i < fr.points.size(); ++i) {
      const FrequencyPoint& p = fr.points[i];
      fmt::print(out, "{},{:.10g},{},{},{:.6e},{:.9e},{:.3e}\n", i, rad_s_to_hz(p.omega),
                 p.converged ? 1 : 0, p.iterations, p.residual_norm, total_dissipation(p),
                 p.residual_norm / solved.system->residual_scale());
    }
  });

  write_file_atomically((dir / "master_response.csv").string(), [&](std::ostream& out) {
    out << "point,body,node,dof,harmonic,real,imag\n";
    for (size_t i = 0; i < fr.points.size(); ++i) {
      const FrequencyPoint& p = fr.points[i];
      for (const PreparedBody& body : model.bodies) {
        for (const auto& [key, g] : body.master_dof) {
          for (size_t h = 0; h < harmonics.size(); ++h) {
            const std::complex<double> x = p.master(g, static_cast<int>(h));
            fmt::print(out, "{},{},{},{},{},{:.10e},{:.10e}\n", i, body.name, key.first,
                       kGlobalAxes[key.second], harmonics[h], x.real(), x.imag());
          }
        }
      }
    }
  });

  // Pair numbering within each contact.
  std::vector<int> pair_in_contact(model.pairs.size());
  {
    std::map<int, int> count;
    for (size_t q = 0; q < model.pairs.size(); ++q) {
      pair_in_contact[q] = count[model.pair_info[q].contact]++;
    }
  }
  write_file_atomically((dir / "contact_forces.csv").string(), [&](std::ostream& out) {
    out << "point,contact,pair,node_a,node_b,frame,axis,harmonic,real,imag\n";
    for (size_t i = 0; i < fr.points.size(); ++i) {
      const FrequencyPoint& p = fr.points[i];
      for (size_t q = 0; q < p.pairs.size(); ++q) {
        const PreparedPair& info = model.pair_info[q];
        const std::string& contact = def.contacts[info.contact].name;
        const PairResponse& r = p.pairs[q];
        for (int row = 0; row < r.force_local.rows(); ++row) {
          for (size_t h = 0; h < harmonics.size(); ++h) {
            const std::complex<double> f = r.force_local(row, static_cast<int>(h));
            fmt::print(out, "{},{},{},{},{},local,{},{},{:.10e},{:.10e}\n", i, contact,
                       pair_in_contact[q], info.node_a_id, info.node_b_id,
                       local_axis(model, static_cast<int>(q), row), harmonics[h], f.real(),
                       f.imag());
          }
        }
        for (int row = 0; row < r.force_global.rows(); ++row) {
          for (size_t h = 0; h < harmonics.size(); ++h) {
            const std::complex<double> f = r.force_global(row, static_cast<int>(h));
            fmt::print(out, "{},{},{},{},{},global,{},{},{:.10e},{:.10e}\n", i, contact,
                       pair_in_contact[q], info.node_a_id, info.node_b_id, kGlobalAxes[row],
                       harmonics[h], f.real(), f.imag());
          }
        }
      }
    }
  });

  write_file_atomically((dir / "contact_state.csv").string(), [&](std::ostream& out) {
    out << "point,contact,pair,node_a,node_b,stick,slip,separation,dissipated_energy\n";
    for (size_t i = 0; i < fr.points.size(); ++i) {
      const FrequencyPoint& p = fr.points[i];
      for (size_t q = 0; q < p.pairs.size(); ++q) {
        const PreparedPair& info = model.pair_info[q];
        const CycleStatistics& c = p.pairs[q].cycle;
        fmt::print(out, "{},{},{},{},{},{:.6f},{:.6f},{:.6f},{:.9e}\n", i,
                   def.contacts[info.contact].name, pair_in_contact[q], info.node_a_id,
                   info.node_b_id, c.stick_fraction, c.slip_fraction, c.separation_fraction,
                   c.dissipated_energy);
      }
    }
  });

  if (!def.output.histories.empty()) {
    write_file_atomically((dir / "histories.csv").string(), [&](std::ostream& out) {
      out << "point,contact,pair,sample,t_over_period,axis,displacement,force\n";
      for (size_t i = 0; i < fr.points.size(); ++i) {
        const FrequencyPoint& p = fr.points[i];
        for (size_t q = 0; q < p.pairs.size(); ++q) {
          const AftSamples& s = p.pairs[q].history;
          if (s.u.size() == 0) continue;
          const int n = static_cast<int>(s.u.cols());
          for (int j = 0; j < n; ++j) {
            for (int row = 0; row < s.u.rows(); ++row) {
              fmt::print(out, "{},{},{},{},{:.8f},{},{:.10e},{:.10e}\n", i,
                         def.contacts[model.pair_info[q].contact].name, pair_in_contact[q], j,
                         static_cast<double>(j) / n, local_axis(model, static_cast<int>(q), row),
                         s.u(row, j), s.f(row, j));
            }
          }
        }
      }
    });
  }

  int converged = 0;
  for (const FrequencyPoint& p : fr.points) converged += p.converged ? 1 : 0;
  write_file_atomically((dir / "summary.json").string(), [&](std::ostream& out) {
    out << "{\n";
    fmt::print(out, "  \"program\": \"stickslip\",\n  \"version\": \"{}\",\n", STICKSLIP_VERSION);
    fmt::print(out, "  \"case_file\": \"{}\",\n", json_escape(def.file));
    fmt::print(out, "  \"title\": \"{}\",\n", json_escape(def.title));
    fmt::print(out, "  \"reduced_dofs\": {},\n  \"contact_pairs\": {},\n  \"unknowns\": {},\n",
               model.num_dofs, model.pairs.size(), solved.system->size());
    fmt::print(out, "  \"points\": {},\n  \"converged_points\": {},\n  \"completed\": {},\n",
               fr.points.size(), converged, fr.completed ? "true" : "false");
    fmt::print(out, "  \"message\": \"{}\",\n", json_escape(fr.message));
    out << "  \"bodies\": [";
    for (size_t b = 0; b < model.bodies.size(); ++b) {
      const PreparedBody& body = model.bodies[b];
      fmt::print(out,
                 "{}\n    {{\"name\": \"{}\", \"full_dofs\": {}, \"reduced_dofs\": {}, "
                 "\"masters\": {}, \"seconds_reduction\": {:.3f}}}",
                 b ? "," : "", json_escape(body.name), body.from_mesh ? body.mesh.num_dofs() : 0,
                 body.reduced.size(), body.master_dof.size() / 3, body.seconds_reduction);
    }
    out << "\n  ],\n";
    fmt::print(
        out,
        "  \"timings\": {{\"prepare_s\": {:.3f}, \"solve_s\": {:.3f}, \"total_s\": {:.3f}}},\n",
        model.seconds_prepare, solved.seconds_solve, seconds_total);
    fmt::print(out, "  \"inputs\": \"{}\"\n", json_escape(describe_case(def)));
    out << "}\n";
  });
}

std::string study_folder(const std::string& parameter, double value) {
  std::string name = parameter.substr(parameter.rfind('.') + 1);
  return fmt::format("{}_{:g}", name, value);
}

// Amplitude of harmonic 1 (the first dynamic harmonic) of each FRF DOF over the converged points.
std::vector<PlotSeries> frf_series(const CaseDefinition& def, const PreparedModel& model,
                                   const SolvedCase& solved, const std::string& prefix) {
  std::vector<PlotSeries> out;
  const auto& fr = solved.response;
  const int h = fr.harmonics.size() > 1 ? 1 : 0;
  for (const ResponseDofDefinition& r : def.output.frf) {
    const int b = model.body_index(r.body);
    const int g = b < 0 ? -1 : model.bodies[b].global_dof(r.node, r.direction);
    if (g < 0) continue;
    PlotSeries s;
    s.label = fmt::format("{}{} node {} {}", prefix, r.body, r.node, kGlobalAxes[r.direction]);
    for (const FrequencyPoint& p : fr.points) {
      if (!p.converged) continue;
      s.x.push_back(rad_s_to_hz(p.omega));
      s.y.push_back(std::abs(p.master(g, h)));
    }
    out.push_back(std::move(s));
  }
  return out;
}

void plot_run(const fs::path& dir, const CaseDefinition& def, const SolvedCase& solved,
              const std::vector<PlotSeries>& frf,
              const std::function<void(const std::string&)>& warn) {
  std::string warning;
  const std::string title = def.title.empty() ? "stickslip" : def.title;
  if (!frf.empty() && !plot_curves(dir, "frf", title, "frequency (Hz)",
                                   "amplitude of harmonic 1 (m)", frf, &warning)) {
    warn(warning);
    return;
  }
  // Contact state along the sweep: mean fractions over all pairs.
  PlotSeries stick{"stick", {}, {}}, slip{"slip", {}, {}}, separation{"separation", {}, {}};
  for (const FrequencyPoint& p : solved.response.points) {
    if (!p.converged || p.pairs.empty()) continue;
    double a = 0, b = 0, c = 0;
    for (const PairResponse& r : p.pairs) {
      a += r.cycle.stick_fraction;
      b += r.cycle.slip_fraction;
      c += r.cycle.separation_fraction;
    }
    const double n = static_cast<double>(p.pairs.size());
    const double f = rad_s_to_hz(p.omega);
    stick.x.push_back(f), stick.y.push_back(a / n);
    slip.x.push_back(f), slip.y.push_back(b / n);
    separation.x.push_back(f), separation.y.push_back(c / n);
  }
  if (!stick.x.empty() && !plot_curves(dir, "contact_state", title, "frequency (Hz)",
                                       "fraction of the cycle (mean over pairs)",
                                       {stick, slip, separation}, &warning)) {
    warn(warning);
  }
  // Hysteresis loops (first tangential axis) of the pairs in output.histories, at the point that
  // dissipates most.
  int best = -1;
  double most = -1;
  for (size_t i = 0; i < solved.response.points.size(); ++i) {
    const FrequencyPoint& p = solved.response.points[i];
    if (p.converged && total_dissipation(p) > most) most = total_dissipation(p), best = int(i);
  }
  if (best < 0) return;
  const FrequencyPoint& p = solved.response.points[best];
  std::vector<PlotSeries> loops;
  for (size_t q = 0; q < p.pairs.size(); ++q) {
    const AftSamples& h = p.pairs[q].history;
    if (h.u.size() == 0) continue;
    PlotSeries s{fmt::format("pair {}", q), {}, {}};
    for (int j = 0; j <= h.u.cols(); ++j) {  // closed loop: repeat the first sample
      s.x.push_back(h.u(0, j % h.u.cols()));
      s.y.push_back(h.f(0, j % h.u.cols()));
    }
    loops.push_back(std::move(s));
  }
  if (!loops.empty() &&
      !plot_curves(dir, "hysteresis", fmt::format("{}: {:.6g} Hz", title, rad_s_to_hz(p.omega)),
                   "relative displacement, first local axis (m)",
                   "contact force, first local axis (N)", loops, &warning)) {
    warn(warning);
  }
}

}  // namespace

int run_case(const RunCommand& command) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const CaseDefinition base = read_case_file(command.case_file);
  const bool quiet = command.quiet || base.output.quiet;
  const auto progress = [&](const std::string& line) {
    if (!quiet) std::fprintf(stderr, "stickslip: %s\n", line.c_str());
  };
  const fs::path out_dir =
      command.output_dir.empty() ? fs::path(base.output.directory) : fs::path(command.output_dir);

  std::vector<std::pair<std::string, CaseDefinition>> runs;
  if (base.study.active()) {
    for (double v : base.study.values) {
      runs.emplace_back(
          study_folder(base.study.parameter, v),
          with_parameter(base, base.study.parameter, v, base.where("study.parameter")));
    }
  } else {
    runs.emplace_back("", base);
  }
  int failed_points = 0;
  std::vector<PlotSeries> overlay;
  const auto warn = [](const std::string& w) {
    std::fprintf(stderr, "stickslip: warning: %s\n", w.c_str());
  };
  for (const auto& [folder, def] : runs) {
    if (!folder.empty()) progress("study: " + folder);
    const auto t_run = Clock::now();
    const PreparedModel model = prepare_model(def, progress);
    const SolvedCase solved = solve_case(model, def, progress);
    const fs::path dir = folder.empty() ? out_dir : out_dir / folder;
    write_results(dir, def, model, solved,
                  std::chrono::duration<double>(Clock::now() - t_run).count());
    std::vector<PlotSeries> full_frf;
    run_recovery(dir, def, model, solved, progress, &full_frf);
    if (def.output.plots) {
      const auto frf = frf_series(def, model, solved, folder.empty() ? "" : folder + ": ");
      plot_run(dir, def, solved, frf, warn);
      if (!full_frf.empty() && full_frf.front().x.size() > 1) {
        // The thesis's validation plot: reduced nonlinear FRF and full-model recovery overlaid.
        std::vector<PlotSeries> both = frf;  // the same curves, relabelled
        for (PlotSeries& c : both) c.label = "reduced: " + c.label;
        both.insert(both.end(), full_frf.begin(), full_frf.end());
        std::string warning;
        if (!plot_curves(dir, "frf_full_vs_reduced", def.title, "frequency (Hz)",
                         "amplitude of harmonic 1 (m)", both, &warning)) {
          warn(warning);
        }
      }
      overlay.insert(overlay.end(), frf.begin(), frf.end());
    }
    int bad = 0;
    for (const FrequencyPoint& p : solved.response.points) bad += p.converged ? 0 : 1;
    failed_points += bad;
    progress(fmt::format("{} points ({} not converged) in {:.2f} s; results in {}",
                         solved.response.points.size(), bad, solved.seconds_solve, dir.string()));
  }
  if (runs.size() > 1 && base.output.plots && !overlay.empty()) {
    std::string warning;
    if (!plot_curves(out_dir, "frf_study", base.title + ": " + base.study.parameter,
                     "frequency (Hz)", "amplitude of harmonic 1 (m)", overlay, &warning)) {
      warn(warning);
    }
  }
  progress(
      fmt::format("done in {:.1f} s", std::chrono::duration<double>(Clock::now() - t0).count()));
  if (failed_points > 0) {
    std::fprintf(stderr, "stickslip: %d frequency points did not converge (see points.csv)\n",
                 failed_points);
    return 1;
  }
  return 0;
}

}  // namespace stickslip
