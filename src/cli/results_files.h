// Reading back the files the stages write into an output folder (docs/output-files.md), so that
// one stage can start from the files of an earlier one:
//   solve   -> points.csv, contact_forces.csv, contact_state.csv, master_response.csv,
//              histories.csv (optional), summary.json (title, frf DOFs, fingerprint)
//   reduce  -> reduced/manifest.txt (what the reduced matrices were made from)
// Every error (missing file, missing column, bad number, unknown pair, missing or repeated
// rows) throws InvalidInput naming the file and line; a missing file also names the command that
// makes it (`hint`, e.g. "stickslip solve case.yaml -o out").
//
// Numbers: every CSV number is the shortest decimal that reads back to the same double (at most
// 17 significant digits), so doubles read back exactly (a recovery from the files equals the one
// in memory to round-off). Columns with a unit name it (real_m, force_n, dissipated_energy_j);
// the direction column is `axis`. Files of earlier versions (`dof`, `real`, `imag`,
// `dissipated_energy`, ... without units) are still read, with a warning naming the file.
#pragma once

#include <complex>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Core>

#include "hbm/frequency_response.h"
#include "io/case_file.h"
#include "io/fingerprint.h"

namespace stickslip {

// fingerprint_hex, file_fingerprint_hex: io/fingerprint.h.

// An existing file, or InvalidInput{path}: "missing: run `<hint>` first".
void require_stage_file(const std::filesystem::path& path, const std::string& hint);

// Identity of a contact pair in the solve outputs.
struct SolvedPairId {
  std::string contact;
  int pair = 0;  // 0-based within the contact
  int node_a = 0, node_b = 0;
  int local_rows = 0;  // 3 (t1, t2, n) or 1 (u)
};

// A master DOF of master_response.csv: (body, external node id, direction 0..2).
using MasterDofKey = std::tuple<std::string, int, int>;

// A bifurcation of summary.json's `bifurcations` (hbm/frequency_response.h).
struct SolvedBifurcation {
  std::string type;  // fold, branch_point, period_doubling, neimark_sacker
  int point = 0;     // between points `point` and `point + 1`
  double frequency_hz = 0.0;
  std::vector<double> amplitude_m;  // per output.frf DOF (summary.json frf order); NaN: none
};

struct SolveResults {
  std::string title;
  std::string fingerprint;                 // of the solve's inputs (summary.json)
  std::vector<ResponseDofDefinition> frf;  // output.frf of the solved case (summary.json)
  // A study folder's studied key and value (summary.json "study"); empty / 0 otherwise.
  std::string study_parameter;
  double study_value = 0.0;
  bool log_amplitude = false;  // the case's output.log_amplitude (summary.json "plots")
  std::vector<SolvedBifurcation> bifurcations;  // summary.json; empty in older files
  // points: omega, converged, iterations, residual_norm, stability_computed, floquet.stable and
  // floquet.max_multiplier (points.csv stable, floquet_multiplier when present and not empty),
  // per pair force_local (local_rows x nh),
  // force_global (3 x nh), cycle statistics and (histories.csv) the sampled cycle. `master` and
  // `unknowns` stay empty (the files hold only the physical master DOFs: see `master` below).
  FrequencyResponse response;
  std::vector<SolvedPairId> pairs;  // in the order of the solve (the model's pair order)
  std::map<MasterDofKey, Eigen::MatrixXcd> master;  // points x harmonics
  // snmt.csv and snmt_response.csv, when the folder has them (analysis.nonlinear_mode): per row
  // of the predicted curve, in its order, the excitation frequency, the mode's frequency (Hz) and
  // harmonic 1 of each physical master DOF.
  struct Prediction {
    std::vector<double> frequency_hz, mode_frequency_hz;
    std::map<MasterDofKey, std::vector<std::complex<double>>> master;
  };
  Prediction prediction;
};

SolveResults read_solve_results(const std::filesystem::path& dir, const std::string& hint);

// The study columns of every per-point table in a study folder (docs/output-files.md): header
// ",parameter,value" and row cells ",<key>,<value>" (value as its shortest exact decimal), so
// that the folders' tables concatenate; both empty without a study.
struct StudyColumns {
  std::string header;
  std::string cells;
};
StudyColumns study_columns(const CaseDefinition& definition, double value);

// Energy dissipated per cycle at a point, J: the sum over its pairs (points.csv's
// dissipated_energy).
double dissipated_energy(const FrequencyPoint& point);

// reduce's manifest: `key value` lines ('#' comments). Keys: "case" (the case file) and
// "body <name>" -> the fingerprint of what the body's reduction was made from.
struct ReduceManifest {
  std::string case_file;
  std::map<std::string, std::string> body_fingerprint;
};
void write_reduce_manifest(const std::filesystem::path& path, const ReduceManifest& manifest);
ReduceManifest read_reduce_manifest(const std::filesystem::path& path);

// Dense matrix as binary: a text line "stickslip-dense-matrix 1 <rows> <cols>\n" and then the
// values as little-endian IEEE doubles, column-major (the Craig–Bampton basis T).
void write_dense_matrix(const std::filesystem::path& path, const Eigen::MatrixXd& matrix);
Eigen::MatrixXd read_dense_matrix(const std::filesystem::path& path);

}  // namespace stickslip
