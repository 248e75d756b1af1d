// `stickslip solve CASE -o DIR`: the harmonic balance of the case (cli/pipeline.h) and its CSV
// and JSON outputs (docs/output-files.md), reusing reduce's matrices when they belong to the case.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>

#include <fmt/core.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/interruption.h"
#include "cli/nonlinear_mode_stage.h"
#include "cli/pipeline.h"
#include "cli/progress.h"
#include "cli/results_files.h"
#include "cli/stale_results.h"
#include "cli/summary_file.h"
#include "core/errors.h"
#include "core/types.h"
#include "io/atomic_file.h"
#include "io/case_file.h"
#include "io/vtu_writer.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

const char* kLocalAxes[3] = {"t1", "t2", "n"};
const char* kGlobalAxes[3] = {"x", "y", "z"};

// Name of the contact pair's axis rows: 3D contacts t1, t2, n; 1D laws "u".
std::string local_axis(const PreparedModel& model, int pair, int row) {
  return model.pairs[pair].frame.rows() == 3 ? kLocalAxes[row] : "u";
}

// summary.json's static_check (docs/output-files.md): with static: uncoupled, how many points
// the check of frequency_response.h flagged and the pairs with the largest mismatch over the
// sweep (at most kWorstPairs, flagged pairs only); with static: coupled, nothing is checked.
Json static_check_json(const CaseDefinition& def, const PreparedModel& model,
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
  Json out;
  out["static"] = uncoupled ? "uncoupled" : "coupled";
  out["threshold"] = kStaticMismatchThreshold;
  out["flagged_points"] = flagged;
  out["worst_pairs"] = Json::array();
  for (const size_t q : order) {
    const PreparedPair& info = model.pair_info[q];
    out["worst_pairs"].push_back({{"contact", def.contacts[info.contact].name},
                                  {"pair", pair_in_contact[q]},
                                  {"node_a", info.node_a_id},
                                  {"node_b", info.node_b_id},
                                  {"point", worst[q].point},
                                  {"mismatch", worst[q].mismatch},
                                  {"separation", worst[q].separation}});
  }
  return out;
}

// summary.json's bifurcations (docs/output-files.md): per bifurcation of the continuation its type,
// the point before it, where it lies (frequency, and the amplitude of harmonic 1 of every
// output.frf DOF, as the FRF plot shows it; null for a DOF that is not a master DOF), whether the
// bisection located it and the critical Floquet multiplier (null without stability).
Json bifurcations_json(const CaseDefinition& def, const PreparedModel& model,
                       const FrequencyResponse& fr) {
  Json list = Json::array();
  for (const Bifurcation& b : fr.bifurcations) {
    const FrequencyPoint& p = b.point;
    Json amplitudes = Json::array();
    for (const ResponseDofDefinition& r : def.output.frf) {
      const int body = model.body_index(r.body);
      const int g = body < 0 ? -1 : model.bodies[body].global_dof(r.node, r.direction);
      const int h = p.master.cols() > 1 ? 1 : 0;  // harmonic 1 (column 0 is the mean)
      amplitudes.push_back(g >= 0 && g < p.master.rows() ? Json(std::abs(p.master(g, h)))
                                                         : Json(nullptr));
    }
    const bool multiplier = std::isfinite(b.multiplier.real());
    list.push_back({{"type", to_string(b.type)},
                    {"point", b.after_point},
                    {"frequency_hz", rad_s_to_hz(p.omega)},
                    {"amplitude_m", amplitudes},
                    {"located", b.located},
                    {"bracket_hz", rad_s_to_hz(b.bracket)},
                    {"multiplier_real", multiplier ? Json(b.multiplier.real()) : Json(nullptr)},
                    {"multiplier_imag", multiplier ? Json(b.multiplier.imag()) : Json(nullptr)},
                    {"message", b.message}});
  }
  return list;
}

}  // namespace

void warn_peak_at_window_edge(const StageRun& run, const PreparedModel& model,
                              const SolvedCase& solved) {
  const SweepWindow& w = solved.window;
  for (const FrfPeak& peak : frf_peaks(run.definition, model, solved.response)) {
    if (!peak.at_edge) continue;
    stderr_warning(fmt::format(
        "{}the response peak of {} node {} {} is at the edge of the sweep window (point {} at "
        "{:.6g} Hz; window {:.6g} to {:.6g} Hz): the true peak may lie outside it; widen "
        "analysis.frequency (summary.json: frf peak_at_window_edge)",
        run.folder.empty() ? "" : run.folder + ": ", peak.dof.body, peak.dof.node,
        kGlobalAxes[peak.dof.direction], peak.point, peak.frequency_hz, w.start_hz, w.stop_hz));
  }
}

std::string describe_removed(const std::vector<std::string>& removed) {
  if (removed.empty()) return "";
  std::string list;
  constexpr size_t kNamed = 5;  // the log names a few; summary.json lists them all
  for (size_t i = 0; i < removed.size() && i < kNamed; ++i) list += (i ? ", " : "") + removed[i];
  if (removed.size() > kNamed) list += fmt::format(" and {} more", removed.size() - kNamed);
  return fmt::format("removed {} file(s) of an earlier run that this one does not write: {}",
                     removed.size(), list);
}

namespace {

// The converged point whose pairs dissipate most in all (the first of equals; -1: none converged),
// with the energies as written (`energy`): the point of the contact map and the hysteresis plots.
int most_dissipative_point(const FrequencyResponse& fr,
                           const std::function<double(const CycleStatistics&)>& energy) {
  int best = -1;
  double most = -1;
  for (size_t i = 0; i < fr.points.size(); ++i) {
    const FrequencyPoint& p = fr.points[i];
    if (!p.converged) continue;
    double e = 0;
    for (const PairResponse& r : p.pairs) e += energy(r.cycle);
    if (e > most) most = e, best = static_cast<int>(i);
  }
  return best;
}

// contact_map.vtu (docs/output-files.md): one VTK vertex per contact pair at its A node (its B
// node when A has no mesh; pairs on bodies given by matrices have no place and are left out), with
// the cycle fractions and the friction energy of the converged point that dissipates most (the
// point the hysteresis plots show). Nothing when no pair has a place or no point converged.
void write_contact_map(const fs::path& dir, const CaseDefinition& def, const PreparedModel& model,
                       const FrequencyResponse& fr,
                       const std::function<double(const CycleStatistics&)>& energy) {
  const int best = most_dissipative_point(fr, energy);
  if (best < 0) return;
  // The coordinates of node `id` of body `name`, if that body has a mesh holding it.
  const auto place = [&](const std::string& name, int id, Eigen::Vector3d* x) {
    const int b = model.body_index(name);
    if (b < 0 || !model.bodies[b].from_mesh || id <= 0) return false;
    const Mesh& mesh = model.bodies[b].mesh;
    const auto it = std::find(mesh.node_ids.begin(), mesh.node_ids.end(), id);
    if (it == mesh.node_ids.end()) return false;
    *x = mesh.coordinates.col(it - mesh.node_ids.begin());
    return true;
  };
  std::vector<int> pairs, ids;
  std::vector<Eigen::Vector3d> places;
  std::map<int, int> count;
  std::vector<int> pair_in_contact;
  for (size_t q = 0; q < model.pair_info.size(); ++q) {
    const PreparedPair& info = model.pair_info[q];
    pair_in_contact.push_back(count[info.contact]++);
    const ContactDefinition& c = def.contacts[info.contact];
    Eigen::Vector3d x;
    if (place(c.body_a, info.node_a_id, &x)) {
      ids.push_back(info.node_a_id);
    } else if (place(c.body_b, info.node_b_id, &x)) {
      ids.push_back(info.node_b_id);
    } else {
      continue;
    }
    pairs.push_back(static_cast<int>(q));
    places.push_back(x);
  }
  if (pairs.empty()) return;
  const int n = static_cast<int>(pairs.size());
  Eigen::Matrix3Xd coordinates(3, n);
  Eigen::MatrixXd stick(1, n), slip(1, n), separation(1, n), dissipated(1, n), contact(1, n),
      pair(1, n), node_a(1, n), node_b(1, n);
  const FrequencyPoint& p = fr.points[best];
  for (int k = 0; k < n; ++k) {
    const int q = pairs[k];
    const CycleStatistics& c = p.pairs[q].cycle;
    coordinates.col(k) = places[k];
    stick(0, k) = c.stick_fraction;
    slip(0, k) = c.slip_fraction;
    separation(0, k) = c.separation_fraction;
    dissipated(0, k) = energy(c);
    contact(0, k) = model.pair_info[q].contact;
    pair(0, k) = pair_in_contact[q];
    node_a(0, k) = model.pair_info[q].node_a_id;
    node_b(0, k) = model.pair_info[q].node_b_id;
  }
  VtuData data;
  data.point_data = {{"stick", stick},
                     {"slip", slip},
                     {"separation", separation},
                     {"dissipated_energy_j", dissipated},
                     {"contact", contact},
                     {"pair", pair},
                     {"node_a", node_a},
                     {"node_b", node_b}};
  data.field_data = {{"frequency_hz", rad_s_to_hz(p.omega)},
                     {"point", static_cast<double>(best)}};
  write_vtu_points((dir / "contact_map.vtu").string(), coordinates, ids, data);
}

}  // namespace

std::vector<std::string> write_solve_results(const StageRun& run, const PreparedModel& model,
                                             const SolvedCase& solved, double seconds_total) {
  const fs::path& dir = run.dir;
  const CaseDefinition& def = run.definition;
  create_output_folder(dir);
  const FrequencyResponse& fr = solved.response;
  const std::vector<int>& harmonics = fr.harmonics;

  // Friction energy per cycle is >= 0, and exactly 0 for a pair that never slips: what the
  // cycle integral gives there is round-off (±1e-21 J). Written as 0: a pair without slip, and
  // values within kEnergyRoundOff of the sweep's largest pair energy (docs/output-files.md).
  constexpr double kEnergyRoundOff = 1e-12;
  double largest_energy = 0;
  for (const FrequencyPoint& p : fr.points) {
    for (const PairResponse& r : p.pairs)
      largest_energy = std::max(largest_energy, std::abs(r.cycle.dissipated_energy));
  }
  const auto energy = [&](const CycleStatistics& c) {
    const double e = c.dissipated_energy;
    return c.slip_fraction == 0 || std::abs(e) <= kEnergyRoundOff * largest_energy ? 0.0 : e;
  };
  // With a study, every row carries the studied parameter and its value: the folders' tables
  // concatenate into one (pandas.concat) without losing which value a row belongs to.
  // Every number in the shortest decimal that reads back to the same double ("{}"), every unit
  // in its column's name (docs/output-files.md, "Tables").
  const StudyColumns study = study_columns(def, run.value);
  const std::string& study_cells = study.cells;
  write_file_atomically((dir / "points.csv").string(), [&](std::ostream& out) {
    // With analysis.stability: whether the point is stable and its largest Floquet multiplier
    // modulus (empty for a point that did not converge).
    const bool stability = def.analysis.stability;
    out << "point,frequency_hz,converged,iterations,residual_m,dissipated_energy_j,"
           "residual_relative,static_mismatch,static_warning,aft_fallback_pairs"
        << (stability ? ",stable,floquet_multiplier,floquet_unplaced" : "") << study.header << "\n";
    for (size_t i = 0; i < fr.points.size(); ++i) {
      const FrequencyPoint& p = fr.points[i];
      double e = 0;
      int fallback = 0;  // pairs whose cycle the event AFT left to the sampled one
      for (const PairResponse& r : p.pairs) {
        e += energy(r.cycle);
        fallback += r.cycle.aft_fallback ? 1 : 0;
      }
      std::string floquet;
      if (stability) {
        floquet = p.stability_computed
                      ? fmt::format(",{},{},{}", p.floquet.stable ? 1 : 0, p.floquet.max_multiplier,
                                    p.floquet.unplaced_exponents)
                      : std::string(",,,");
      }
      fmt::print(out, "{},{},{},{},{},{},{},{},{},{}{}{}\n", i, rad_s_to_hz(p.omega),
                 p.converged ? 1 : 0, p.iterations, p.residual_norm, e,
                 p.residual_norm / p.residual_scale, p.static_mismatch, p.static_warning ? 1 : 0,
                 fallback, floquet, study.cells);
    }
  });

  write_file_atomically((dir / "master_response.csv").string(), [&](std::ostream& out) {
    out << "point,body,node,axis,harmonic,real_m,imag_m" << study.header << "\n";
    for (size_t i = 0; i < fr.points.size(); ++i) {
      const FrequencyPoint& p = fr.points[i];
      for (const PreparedBody& body : model.bodies) {
        for (const auto& [key, g] : body.master_dof) {
          for (size_t h = 0; h < harmonics.size(); ++h) {
            const std::complex<double> x = p.master(g, static_cast<int>(h));
            fmt::print(out, "{},{},{},{},{},{},{}{}\n", i, body.name, key.first,
                       kGlobalAxes[key.second], harmonics[h], x.real(), x.imag(), study_cells);
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
    out << "point,contact,pair,node_a,node_b,frame,axis,harmonic,real_n,imag_n" << study.header
        << "\n";
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
              fmt::print(out, "{},{},{},{},{},{},{},{},{},{}{}\n", i, contact,
                         pair_in_contact[q], info.node_a_id, info.node_b_id, frame, axis_name(row),
                         harmonics[h], f.real(), f.imag(), study_cells);
            }
          }
        };
        rows("local", r.force_local,
             [&](int row) { return local_axis(model, static_cast<int>(q), row); });
        // A mortar point's force_global has a row per frame column; its first three over
        // weight_a are the point's force on B (case_model.h, PreparedPair).
        rows("global",
             r.force_global.topRows(std::min<Eigen::Index>(3, r.force_global.rows())) /
                 info.weight_a,
             [](int row) { return std::string(kGlobalAxes[row]); });
      }
    }
  });

  // Mortar contacts: how each point is tied to B (docs/output-files.md, contact_coupling.csv).
  const bool any_mortar = std::any_of(model.pair_info.begin(), model.pair_info.end(),
                                      [](const PreparedPair& info) { return info.mortar; });
  if (any_mortar) {
    write_file_atomically((dir / "contact_coupling.csv").string(), [&](std::ostream& out) {
      out << "contact,pair,node_a,area_m2,gap_m,node_b,weight,faces_b,nodes_a,weights_a\n";
      for (size_t q = 0; q < model.pair_info.size(); ++q) {
        const PreparedPair& info = model.pair_info[q];
        if (!info.mortar) continue;
        std::string faces, nodes_a, weights_a;
        for (int e : info.partner_elements) faces += (faces.empty() ? "" : " ") + std::to_string(e);
        for (size_t j = 0; j < info.point_ids_a.size(); ++j) {
          nodes_a += (j ? " " : "") + std::to_string(info.point_ids_a[j]);
          weights_a += fmt::format("{}{}", j ? " " : "", info.point_weights_a[j]);
        }
        for (size_t k = 0; k < info.partner_ids.size(); ++k) {
          fmt::print(out, "{},{},{},{},{},{},{},{},{},{}\n", def.contacts[info.contact].name,
                     pair_in_contact[q], info.node_a_id, info.area, info.gap, info.partner_ids[k],
                     info.weights[k], faces, nodes_a, weights_a);
        }
      }
    });
  }

  write_file_atomically((dir / "contact_state.csv").string(), [&](std::ostream& out) {
    out << "point,contact,pair,node_a,node_b,stick,slip,separation,dissipated_energy_j"
        << study.header << "\n";
    for (size_t i = 0; i < fr.points.size(); ++i) {
      const FrequencyPoint& p = fr.points[i];
      for (size_t q = 0; q < p.pairs.size(); ++q) {
        const PreparedPair& info = model.pair_info[q];
        const CycleStatistics& c = p.pairs[q].cycle;
        fmt::print(out, "{},{},{},{},{},{},{},{},{}{}\n", i, def.contacts[info.contact].name,
                   pair_in_contact[q], info.node_a_id, info.node_b_id, c.stick_fraction,
                   c.slip_fraction, c.separation_fraction, energy(c), study_cells);
      }
    }
  });

  write_contact_map(dir, def, model, fr, energy);

  // With output.histories, the cycle of the pair that dissipates most at the most dissipative
  // point is kept too (when not asked for already): the hysteresis plots show it beside the
  // requested pairs (docs/output-files.md).
  int loop_point = -1, loop_pair = -1;
  AftSamples loop;
  if (!def.output.histories.empty() && solved.system) {
    loop_point = most_dissipative_point(fr, energy);
    if (loop_point >= 0) {
      const FrequencyPoint& p = fr.points[loop_point];
      double most = 0;
      for (size_t q = 0; q < p.pairs.size(); ++q) {
        if (energy(p.pairs[q].cycle) > most) {
          most = energy(p.pairs[q].cycle), loop_pair = static_cast<int>(q);
        }
      }
      if (loop_pair >= 0 && p.pairs[loop_pair].history.u.size() == 0 && p.unknowns.size() > 0) {
        loop = solved.system->pair_cycle(p.unknowns, loop_pair);
      }
    }
  }
  if (!def.output.histories.empty()) {
    write_file_atomically((dir / "histories.csv").string(), [&](std::ostream& out) {
      out << "point,contact,pair,sample,t_over_period,axis,displacement_m,force_n" << study.header
          << "\n";
      for (size_t i = 0; i < fr.points.size(); ++i) {
        const FrequencyPoint& p = fr.points[i];
        for (size_t q = 0; q < p.pairs.size(); ++q) {
          const bool extra = static_cast<int>(i) == loop_point &&
                             static_cast<int>(q) == loop_pair && loop.u.size() > 0;
          const AftSamples& s = extra ? loop : p.pairs[q].history;
          if (s.u.size() == 0) continue;
          const int n = static_cast<int>(s.u.cols());
          for (int j = 0; j < n; ++j) {
            for (int row = 0; row < s.u.rows(); ++row) {
              fmt::print(out, "{},{},{},{},{},{},{},{}{}\n", i,
                         def.contacts[model.pair_info[q].contact].name, pair_in_contact[q], j,
                         static_cast<double>(j) / n, local_axis(model, static_cast<int>(q), row),
                         s.u(row, j), s.f(row, j), study_cells);
            }
          }
        }
      }
    });
  }

  if (def.analysis.predict_from_mode) write_prediction_tables(run, model, solved);

  // Results of an earlier run in this folder: gone before this run's summary is written.
  const std::vector<std::string> removed = remove_stale_results(dir, ResultFamily::kEverything);

  int converged = 0;
  for (const FrequencyPoint& p : fr.points) converged += p.converged ? 1 : 0;
  Json summary = start_summary(run);
  summary["plots"] = {{"log_amplitude", def.output.log_amplitude}};
  const SweepWindow& w = solved.window;
  summary["window"] = {{"start_hz", w.start_hz},
                       {"stop_hz", w.stop_hz},
                       {"stuck_mode", w.stuck_mode > 0 ? Json(w.stuck_mode) : Json(nullptr)},
                       {"stuck_mode_hz", w.stuck_mode > 0 ? Json(w.stuck_mode_hz) : Json(nullptr)}};
  summary["frf"] = Json::array();
  for (const FrfPeak& peak : frf_peaks(def, model, fr)) {
    Json entry = {{"body", peak.dof.body},
                  {"node", peak.dof.node},
                  {"direction", kGlobalAxes[peak.dof.direction]}};
    if (peak.point >= 0) {
      entry["peak_point"] = peak.point;
      entry["peak_frequency_hz"] = peak.frequency_hz;
      entry["peak_amplitude_m"] = peak.amplitude_m;
      entry["peak_at_window_edge"] = peak.at_edge;
      entry["peak_located"] = peak.located;
      entry["peak_message"] = peak.message;
    }
    summary["frf"].push_back(entry);
  }
  summary["reduced_dofs"] = model.num_dofs;
  summary["contact_pairs"] = model.pairs.size();
  summary["unknowns"] = solved.system->size();
  summary["points"] = fr.points.size();
  summary["converged_points"] = converged;
  summary["completed"] = fr.completed;
  summary["message"] = fr.message;
  summary["static_check"] = static_check_json(def, model, solved, pair_in_contact);
  int fallback_points = 0;  // points where some pair's cycle came from the sampled AFT
  for (const FrequencyPoint& p : fr.points) {
    bool any = false;
    for (const PairResponse& r : p.pairs) any = any || r.cycle.aft_fallback;
    fallback_points += any ? 1 : 0;
  }
  summary["aft"] = {{"method", case_name(def.analysis.aft)},
                    {"time_samples", def.analysis.time_samples},
                    {"fallback_points", fallback_points}};
  if (def.analysis.stability) {  // Hill's method (points.csv stable, floquet_multiplier)
    int unstable = 0, unplaced = 0;
    double largest = 0;
    for (const FrequencyPoint& p : fr.points) {
      if (!p.stability_computed) continue;
      unstable += p.floquet.stable ? 0 : 1;
      unplaced += p.floquet.unplaced_exponents > 0 ? 1 : 0;
      if (std::isfinite(p.floquet.max_multiplier)) {
        largest = std::max(largest, p.floquet.max_multiplier);
      }
    }
    summary["stability"] = {{"unstable_points", unstable},
                            {"largest_multiplier", largest},
                            {"unplaced_points", unplaced}};
  } else {
    summary["stability"] = nullptr;
  }
  summary["bifurcations"] = bifurcations_json(def, model, fr);
  if (def.analysis.predict_from_mode) {
    summary["nonlinear_mode"] = prediction_summary(def, model, solved);
  }
  finish_summary(summary, run, model, solved.seconds_solve, seconds_total, removed);
  write_summary(dir, summary);
  return removed;
}

SolveOutcome report_solved(const SolvedCase& solved, const fs::path& dir,
                           const ProgressFn& progress) {
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
  int inexact = 0;  // points where the event AFT fell back to the sampled one for some pair
  for (const FrequencyPoint& p : solved.response.points) {
    bool fallback = false;
    for (const PairResponse& r : p.pairs) fallback = fallback || r.cycle.aft_fallback;
    inexact += fallback ? 1 : 0;
  }
  if (inexact > 0 && solved.warn_aft_fallback) {
    std::fprintf(stderr,
                 solved.system->options().aft == AftMethod::kEventPlanar
                     ? "stickslip: warning: `analysis.aft: event_planar` could not close the "
                       "cycle of some pairs at %d of %zu points: their forces come from the "
                       "sampled AFT with time_samples = %d (points.csv aft_fallback_pairs; error "
                       "at the stick/slip and lift-off instants; raise time_samples to check)\n"
                     : "stickslip: warning: `analysis.aft: event` is exact only for contacts "
                       "whose tangential motion stays on one line; at %d of %zu points some "
                       "pairs moved in the tangent plane and their forces come from the sampled "
                       "AFT with time_samples = %d (points.csv aft_fallback_pairs; error at the "
                       "stick/slip and lift-off instants; raise time_samples to check, or use "
                       "`aft: event_planar`, exact and slower: docs/performance.md)\n",
                 inexact, solved.response.points.size(),
                 solved.system->options().time_samples);
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
  int unplaced_points = 0, unplaced = 0;  // Hill's method: families without a centred member
  for (const FrequencyPoint& p : solved.response.points) {
    if (!p.stability_computed || p.floquet.unplaced_exponents == 0) continue;
    ++unplaced_points;
    unplaced = std::max(unplaced, p.floquet.unplaced_exponents);
  }
  if (unplaced_points > 0) {  // a warning, printed even with --quiet
    std::fprintf(stderr,
                 "stickslip: warning: at %d of %zu points Hill's method could not place up to %d "
                 "Floquet exponents (no member of their family is centred on harmonic 0 within "
                 "the %d harmonics: the truncation decides them); `stable` and "
                 "`floquet_multiplier` are those of the others (points.csv floquet_unplaced; "
                 "raise analysis.harmonics to check; docs/conventions.md \"Stability\")\n",
                 unplaced_points, solved.response.points.size(), unplaced,
                 solved.system->unknown_harmonics().max_harmonic());
  }
  SolveOutcome outcome{.failed_points = failed};
  // A stepped sweep is incomplete exactly when points failed (said above and at the end); a
  // continuation can stop with every point converged and the range not covered.
  if (!solved.response.completed && failed == 0) {
    outcome.incomplete_analyses = 1;
    const double first = solved.frequencies_hz.front(), last = solved.frequencies_hz.back();
    double reached = first;
    for (const FrequencyPoint& p : solved.response.points) {
      const double hz = p.omega / (2 * kPi);
      if (std::abs(hz - first) > std::abs(reached - first)) reached = hz;
    }
    std::fprintf(stderr,
                 "stickslip: the analysis stopped at %.6g Hz, %.0f %% of the way from %.6g to "
                 "%.6g Hz (%s; results in %s): %s\n",
                 reached, 100 * std::abs(reached - first) / std::abs(last - first), first, last,
                 solved.response.points.empty() ? "no points" : "the points before are written",
                 dir.string().c_str(), solved.response.message.c_str());
  }
  return outcome;
}

int solve_exit_code(double seconds, const SolveOutcome& outcome, const ProgressFn& progress) {
  progress(fmt::format("done in {:.1f} s", seconds));
  if (outcome.failed_points > 0) {
    std::fprintf(stderr, "stickslip: %d frequency points did not converge (see points.csv)\n",
                 outcome.failed_points);
  }
  if (outcome.incomplete_analyses > 0) {
    std::fprintf(stderr,
                 "stickslip: %d analyses stopped before the end of their frequency range (see "
                 "summary.json \"message\")\n",
                 outcome.incomplete_analyses);
  }
  return outcome.failed_points > 0 || outcome.incomplete_analyses > 0 ? 1 : 0;
}

int run_solve(const StageCommand& command) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const CaseDefinition base = read_case_file(command.case_file);
  const bool quiet = command.quiet || base.output.quiet;
  const auto progress = stderr_progress(quiet);
  ProgressReporter reporter(std::cerr, stderr_progress_options(quiet));
  const fs::path out_dir = stage_output_dir(base, command.output_dir);
  SolveOutcome outcome;
  ModelCache cache;  // meshes and reductions shared by the study's analyses
  for (const StageRun& run : stage_runs(base, out_dir)) {
    if (!run.folder.empty()) progress("study: " + run.folder);
    const auto t_run = Clock::now();
    interruption_doing("solving for " + run.dir.string());
    const PreparedModel model =
        prepare_stage_model(run, out_dir, command.case_file, /*full_matrices=*/false, progress,
                            /*load_basis_if_present=*/false, &cache);
    if (run.definition.analysis.method == SweepMethod::kNonlinearMode) {
      outcome += run_nonlinear_mode_stage(run, model, progress, &reporter, nullptr, t_run);
      continue;
    }
    const SolvedCase solved = solve_case(model, run.definition, progress, &reporter);
    interruption_doing("writing the solve files in " + run.dir.string());
    const auto removed = write_solve_results(
        run, model, solved, std::chrono::duration<double>(Clock::now() - t_run).count());
    if (!removed.empty()) progress(describe_removed(removed));
    warn_peak_at_window_edge(run, model, solved);
    interruption_done("solve files in " + run.dir.string());
    outcome += report_solved(solved, run.dir, progress);
  }
  return solve_exit_code(std::chrono::duration<double>(Clock::now() - t0).count(), outcome,
                         progress);
}

}  // namespace stickslip
