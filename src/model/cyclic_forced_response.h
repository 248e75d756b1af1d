// The forced response of a cyclic sector under engine-order excitation (issue 13, item 3;
// docs/cyclic.md): what prepare_model does differently for a case whose bodies are one sector of
// N (a blade with its disk, a damper: every body of the case).
//
//   each body with boundaries (low/high): its Craig–Bampton per nodal diameter
//   (reduction/cyclic_craig_bampton.h) onto its master nodes, diameter 0 its ordinary (real)
//   reduced model; each body without: its ordinary Craig–Bampton, the same in every diameter;
//   per dynamic harmonic (diameter k·EO mod N, conjugated above N/2) the assembled model of all
//   bodies gives the TravellingWave (hbm/travelling_wave.h) the harmonic balance takes; contacts
//   with `neighbour` get ContactPair::b_sector.
//
// Scope, each refusal an InvalidInput at the case key it is about: every body of the case is a
// mesh body with `cyclic`, the same N and axis (clamps and supports along the global axes); every
// excitation entry gives the same `engine_order`, and no entry of a case without a cyclic body
// gives one; contacts with `neighbour` join two bodies of the sector (not the ground); Rayleigh
// damping only (no modal_damping_ratio); the window in Hz (no around_mode: the stuck modes of a
// diameter are not computed); method stepped or continuation; recovery direct only; not through
// the stage commands.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "fe/cyclic.h"
#include "hbm/travelling_wave.h"
#include "io/case_file.h"
#include "model/case_model.h"
#include "reduction/cyclic_craig_bampton.h"

namespace stickslip {

struct CyclicForcedResponse {
  std::string body;                 // the first body with boundaries (else the first body)
  std::vector<std::string> bodies;  // every body of the case: the bodies of the sector
  int engine_order = 0;
  CyclicSymmetry symmetry;
};

// The cyclic body of a forced-response case, checked as above, or nothing (a case without one;
// then `engine_order` and `neighbour` are refused at their keys).
std::optional<CyclicForcedResponse> cyclic_forced_response(const CaseDefinition& definition);

// The nodal diameters the analysis reaches: 0 and those of its dynamic harmonics.
std::vector<int> reached_nodal_diameters(const CaseDefinition& definition, int engine_order,
                                         int sectors);

// Reduces the cyclic body per nodal diameter (`diameters`), fills `body` like a Craig–Bampton
// reduction with diameter 0's model (reduced, constraints, K, M; no basis T) and returns every
// diameter's reduced model (same masters, same number of modes).
std::map<int, CyclicReducedSector> reduce_cyclic_body(const CaseDefinition& definition,
                                                      const CaseBody& resolved, PreparedBody& body,
                                                      const std::vector<int>& diameters,
                                                      const ProgressFn& progress);

// The wave of the analysis's dynamic harmonics: per harmonic the complex modes (damping
// c_r = α + βω_r²) of the assembled model of its diameter, block diagonal over the bodies of
// `model` (their offsets): a body with boundaries by its reduction of that diameter
// (`reductions`: body -> diameter -> model, reduce_cyclic_body), a body without by its ordinary
// reduced model (model.bodies[b].reduced), the same for every diameter. A body held only by
// contacts (a damper) brings rigid-body modes (ω² = 0), whose receptance 1/(−(kΩ)² + ikΩα) is
// finite for k ≥ 1.
TravellingWave cyclic_travelling_wave(
    const CaseDefinition& definition, const CyclicForcedResponse& cyclic,
    const PreparedModel& model,
    const std::map<std::string, std::map<int, CyclicReducedSector>>& reductions);

}  // namespace stickslip
