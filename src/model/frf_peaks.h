// The response peaks of a solved case, as its FRF plots and summary.json show them (`run`, `solve`)
// and as a library user asks for them (the Python module's Solution.frf_peaks).
#pragma once

#include <string>
#include <vector>

#include "hbm/frequency_response.h"
#include "io/case_file.h"
#include "model/case_model.h"

namespace stickslip {

// Per output.frf DOF of the case, the largest amplitude of its first dynamic harmonic over the
// converged points (as the FRF plot shows it), m, and where it is; at_edge when that point is the
// first or the last converged point of the sweep (the peak may lie outside the window). A
// continuation locates the maximum between its points (FrequencyResponse::peaks): then located is
// true and frequency_hz and amplitude_m are the located maximum's (point stays the sampled one).
struct FrfPeak {
  ResponseDofDefinition dof;
  int point = -1;  // -1: no converged point, or not a master DOF
  double frequency_hz = 0.0, amplitude_m = 0.0;
  bool at_edge = false;
  bool located = false;
  std::string message;  // how the peak was found (located, or why not)
};
std::vector<FrfPeak> frf_peaks(const CaseDefinition& definition, const PreparedModel& model,
                               const FrequencyResponse& response);

}  // namespace stickslip
