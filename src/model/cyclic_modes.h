// Linear modes of a cyclic sector per nodal diameter (issue 13, item 1; docs/cyclic.md): for a
// case whose body is one sector of N (bodies.B.cyclic), for each nodal diameter h = 0..⌊N/2⌋ the
// lowest natural frequencies of the whole structure whose field repeats from sector to sector
// with the phase 2πh/N (u_high = e^{i2πh/N} R u_low, fe/cyclic.h), with the body's clamps and
// supports along the global axes. For 0 < h < N/2 each frequency is a double mode of the whole
// structure (two standing waves, or the forward and backward travelling waves) and is listed once.
//
// Scope, each refusal an InvalidInput at the case key it is about: the case holds that body only
// (bodies), no contacts (contacts.C: contacts of a sector, with itself or its neighbour, come with
// the forced response), no *EQUATION or supports in a local frame (bodies.B.supports: the
// equations would have to be made cyclic too). The body's full K and M (its mass_rule) are those
// of the Craig–Bampton reduction; the eigen-solve is model-free (linalg/modal.h), so the
// frequencies are those of the full sector, not of a reduced model.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/case_file.h"
#include "linalg/modal.h"
#include "model/case_model.h"

namespace stickslip {

struct NodalDiameterModes {
  int nodal_diameter = 0;
  bool doubled = false;            // 0 < h < N/2: each frequency a double mode of the structure
  Eigen::VectorXd frequencies_hz;  // ascending, each mode once
  ModalSummary summary;            // the eigen-solve (of the real form, twice the size if doubled)
};

struct CyclicModes {
  std::string body;
  int sectors = 0;
  int sector_dofs = 0;  // the sector's independent DOFs (free, off the high boundary)
  std::vector<NodalDiameterModes> diameters;  // h = 0, 1, ..., ⌊N/2⌋
};

// The `modes_per_diameter` (≥ 1) lowest modes of each nodal diameter (fewer where the sector has
// fewer DOFs). `progress` (may be null) gets a line per nodal diameter. A failed eigen-solve
// is a value (summary) the caller reports, never a partial table presented as complete.
CyclicModes cyclic_modes(const CaseDefinition& definition, int modes_per_diameter,
                         const ProgressFn& progress, ModelCache* cache = nullptr);

}  // namespace stickslip
