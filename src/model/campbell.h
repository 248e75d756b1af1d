// The Campbell diagram of a rotating case (rotation.campbell, docs/rotation.md): the natural
// frequencies against the speed of rotation, for every speed of rotation.campbell.speeds_rpm.
//
// At each speed the case is the case at that speed (rotation.speed_rpm replaced): every body is
// reduced again with its stiffness at that speed (model/rotation_case.h: stress stiffening and
// spin softening by the case's flags), and the frequencies are those of the assembled reduced model
//   stuck   every contact stuck (stuck_stiffness_matrix: friction pairs as springs kt, kt, kn),
//   free    the contacts removed (the bodies' reduced K, M alone),
// or, for a cyclic sector (its case holds no contacts, model/cyclic_modes.h), the free sector per
// nodal diameter h = 0..⌊N/2⌋ on the full sector's matrices. Frequencies in the frame that turns
// with the structure (no Coriolis term). Line j of a system joins the j-th lowest frequency of
// every speed: two modes that cross swap lines. A negative ω² (a mode that the spin softening
// makes divergent, e.g. a free body's radial rigid motion) is given as the negative frequency
// −√|ω²|/2π.
#pragma once

#include <string>
#include <vector>

#include "io/case_file.h"
#include "model/case_model.h"

namespace stickslip {

struct CampbellLine {
  std::string system;                  // "stuck" | "free"
  int nodal_diameter = -1;             // a cyclic sector's h; -1 otherwise
  int mode = 0;                        // 1-based, at each speed the mode-th lowest
  std::vector<double> frequencies_hz;  // one per speed
};

struct CampbellDiagram {
  std::vector<double> speeds_rpm;
  std::vector<CampbellLine> lines;
  std::vector<int> engine_orders;  // rotation.campbell.engine_orders
};

// `num_modes` (≥ 1) lowest modes of each system (and nodal diameter) at each speed. InvalidInput
// at `rotation` when the case has no rotation.campbell; an eigen-solve that fails throws
// InvalidInput naming the speed. `cache` as prepare_model's.
CampbellDiagram campbell_diagram(const CaseDefinition& definition, int num_modes,
                                 const ProgressFn& progress, ModelCache* cache = nullptr);

// The frequency of an eigenvalue ω² of the diagram: sign(ω²) √|ω²| / 2π, Hz.
double signed_frequency_hz(double omega2);

}  // namespace stickslip
