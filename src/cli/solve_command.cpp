// `stickslip solve CASE -o DIR`: the harmonic balance of the case (cli/pipeline.h) and its CSV
// and JSON outputs (docs/output-files.md), reusing reduce's matrices when they belong to the case.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>

#include <fmt/core.h>
#include <fmt/ostream.h>

#include "cli/commands.h"
#include "cli/interruption.h"
#include "cli/pipeline.h"
#include "cli/progress.h"
#include "cli/results_files.h"
#include "core/errors.h"
#include "core/types.h"
#include "io/atomic_file.h"
#include "io/case_file.h"

#ifndef STICKSLIP_VERSION
#define STICKSLIP_VERSION "unknown"
#endif

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

// Name of the contact pair's axis rows: 3D contacts t1, t2, n; 1D laws "u".
std::string local_axis(const PreparedModel& model, int pair, int row) {
  return model.pairs[pair].frame.rows() == 3 ? kLocalAxes[row] : "u";
}

// summary.json's static_check (docs/output-files.md): with static: uncoupled, how many points
// the check of frequency_response.h flagged and the pairs with the largest mismatch over the
// sweep (at most kWorstPairs, flagged pairs only); with static: coupled, nothing is checked.
std::string static_check_json(const CaseDefinition& def, const PreparedModel& model,
                              const SolvedCase& solved, const std::vector<int>& pair_in_contact) {
  constexpr size_t kWorstPairs = 5;
  const bool uncoupled = !solved.system->unknown_harmonics().has_static();
  const FrequencyResponse& fr = solved.response;
  int flagged = 0;
  struct Worst {
    double mismatch = 0, separation = 0;
    int point = -1;
  };
  std::vector<Worst> worst(model.pairs.size());
  for (size_t i = 0; i < fr.points.size(); ++i) {
    const FrequencyPoint& p = fr.points[i];
    flagged += p.static_warning ? 1 : 0;
    for (size_t q = 0; q < p.pairs.size() && uncoupled; ++q) {
      const PairResponse& r = p.pairs[q];
      const bool bad = r.static_mismatch > kStaticMismatchThreshold || separates_in_part(r.cycle);
      if (bad && (worst[q].point < 0 || r.static_mismatch > worst[q].mismatch)) {
        worst[q] = {r.static_mismatch, r.cycle.separation_fraction, static_cast<int>(i)};
      }
    }
  }
  std::vector<size_t> order;
  for (size_t q = 0; q < worst.size(); ++q) {
    if (worst[q].point >= 0) order.push_back(q);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return worst[a].mismatch > worst[b].mismatch; });
  if (order.size() > kWorstPairs) order.resize(kWorstPairs);
  std::string out = fmt::format(
      "{{\"static\": \"{}\", \"threshold\": {}, \"flagged_points\": {}, \"worst_pairs\": [",
      uncoupled ? "uncoupled" : "coupled", kStaticMismatchThreshold, flagged);
  for (size_t n = 0; n < order.size(); ++n) {
    const size_t q = order[n];
    const PreparedPair& info = model.pair_info[q];
    out += fmt::format(
        "{}{{\"contact\": \"{}\", \"pair\": {}, \"node_a\": {}, \"node_b\": {}, "
        "\"point\": {}, \"mismatch\": {:.3e}, \"separation\": {:.3f}}}",
        n ? ", " : "", json_escape(def.contacts[info.contact].name), pair_in_contact[q],
        info.node_a_id, info.node_b_id, worst[q].point, worst[q].mismatch, worst[q].separation);
  }
  return out + "]}";
}

}  // namespace

void write_solve_results(const fs::path& dir, const CaseDefinition& def, const PreparedModel& model,
                         const SolvedCase& solved, double seconds_total) {
  create_output_folder(dir);
  const FrequencyResponse& fr = solved.response;
  const std::vector<int>& harmonics = fr.harmonics;

  write_file_atomically((dir / "points.csv").string(), [&](std::ostream& out) {
    out << "point,frequency_hz,converged,iterations,residual,dissipated_energy,residual_relative,"
           "static_mismatch,static_warning\n";
    for (size_t i = 0; i < fr.points.size(); ++i) {
      const FrequencyPoint& p = fr.points[i];
      fmt::print(out, "{},{},{},{},{:.6e},{:.9e},{:.3e},{:.3e},{}\n", i, rad_s_to_hz(p.omega),
                 p.converged ? 1 : 0, p.iterations, p.residual_norm, dissipated_energy(p),
                 p.residual_norm / p.residual_scale, p.static_mismatch, p.static_warning ? 1 : 0);
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
            fmt::print(out, "{},{},{},{},{},{},{}\n", i, body.name, key.first,
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
        const auto rows = [&](const char* frame, const Eigen::MatrixXcd& force, auto axis_name) {
          for (int row = 0; row < force.rows(); ++row) {
            for (size_t h = 0; h < harmonics.size(); ++h) {
              const std::complex<double> f = force(row, static_cast<int>(h));
              fmt::print(out, "{},{},{},{},{},{},{},{},{},{}\n", i, contact,
                         pair_in_contact[q], info.node_a_id, info.node_b_id, frame, axis_name(row),
                         harmonics[h], f.real(), f.imag());
            }
          }
        };
        rows("local", r.force_local,
             [&](int row) { return local_axis(model, static_cast<int>(q), row); });
        rows("global", r.force_global, [](int row) { return std::string(kGlobalAxes[row]); });
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
    fmt::print(out, "  \"fingerprint\": \"{}\",\n", solve_fingerprint(def));
    out << "  \"frf\": [";
    for (size_t i = 0; i < def.output.frf.size(); ++i) {
      const ResponseDofDefinition& r = def.output.frf[i];
      fmt::print(out, "{}\"{}:{}:{}\"", i ? ", " : "", json_escape(r.body), r.node,
                 kGlobalAxes[r.direction]);
    }
    out << "],\n";
    fmt::print(out, "  \"reduced_dofs\": {},\n  \"contact_pairs\": {},\n  \"unknowns\": {},\n",
               model.num_dofs, model.pairs.size(), solved.system->size());
    fmt::print(out, "  \"points\": {},\n  \"converged_points\": {},\n  \"completed\": {},\n",
               fr.points.size(), converged, fr.completed ? "true" : "false");
    fmt::print(out, "  \"message\": \"{}\",\n", json_escape(fr.message));
    out << "  \"static_check\": " << static_check_json(def, model, solved, pair_in_contact)
        << ",\n";
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

int report_solved(const SolvedCase& solved, const fs::path& dir, const ProgressFn& progress) {
  int failed = 0;
  for (const FrequencyPoint& p : solved.response.points) failed += p.converged ? 0 : 1;
  progress(fmt::format("{} points ({} not converged) in {:.2f} s; results in {}",
                       solved.response.points.size(), failed, solved.seconds_solve, dir.string()));
  int flagged = 0, separating = 0;
  for (const FrequencyPoint& p : solved.response.points) {
    flagged += p.static_warning ? 1 : 0;
    bool open = false;
    for (const PairResponse& r : p.pairs) open = open || separates_in_part(r.cycle);
    separating += p.static_warning && open ? 1 : 0;
  }
  if (flagged > 0) {  // a warning, printed even with --quiet
    std::fprintf(stderr,
                 "stickslip: warning: at %d of %zu points the frozen static state of `static: "
                 "uncoupled` is wrong (%d with contacts that separate, the others with a "
                 "cycle-mean contact force more than %g %% away from the static one: slip with "
                 "an offset); the mean contact state changes with the vibration there: use "
                 "`analysis.static: coupled` (points.csv static_warning, summary.json "
                 "static_check in %s)\n",
                 flagged, solved.response.points.size(), separating,
                 100 * kStaticMismatchThreshold, dir.string().c_str());
  }
  return failed;
}

int solve_exit_code(double seconds, int failed_points, const ProgressFn& progress) {
  progress(fmt::format("done in {:.1f} s", seconds));
  if (failed_points > 0) {
    std::fprintf(stderr, "stickslip: %d frequency points did not converge (see points.csv)\n",
                 failed_points);
    return 1;
  }
  return 0;
}

int run_solve(const StageCommand& command) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const CaseDefinition base = read_case_file(command.case_file);
  const bool quiet = command.quiet || base.output.quiet;
  const auto progress = stderr_progress(quiet);
  ProgressReporter reporter(std::cerr, stderr_progress_options(quiet));
  const fs::path out_dir = stage_output_dir(base, command.output_dir);
  int failed_points = 0;
  ModelCache cache;  // meshes and reductions shared by the study's analyses
  for (const StageRun& run : stage_runs(base, out_dir)) {
    if (!run.folder.empty()) progress("study: " + run.folder);
    const auto t_run = Clock::now();
    interruption_doing("solving for " + run.dir.string());
    const PreparedModel model =
        prepare_stage_model(run, out_dir, command.case_file, /*full_matrices=*/false, progress,
                            /*load_basis_if_present=*/false, &cache);
    const SolvedCase solved = solve_case(model, run.definition, progress, &reporter);
    interruption_doing("writing the solve files in " + run.dir.string());
    write_solve_results(run.dir, run.definition, model, solved,
                        std::chrono::duration<double>(Clock::now() - t_run).count());
    interruption_done("solve files in " + run.dir.string());
    failed_points += report_solved(solved, run.dir, progress);
  }
  return solve_exit_code(std::chrono::duration<double>(Clock::now() - t0).count(), failed_points,
                         progress);
}

}  // namespace stickslip
