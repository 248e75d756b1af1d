// The smallest complete case of the reference joint, shared by the case-file tests: it gives
// every required key and nothing optional, so the parser fills in every default.
#pragma once

#include <string>

namespace stickslip::testing_cases {

inline const std::string kMinimalCase = R"(stickslip: 1
materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}
meshes:
  joint: {generate: two_beam}
bodies:
  beam1: {mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1}
  beam2: {mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2}
contacts:
  - name: joint
    law: friction
    between: {beam1: CONTACT1, beam2: CONTACT2}
    normal: [1, 0, 0]
    per_pair: {kt: 4.467e9, kn: 5.6309e9, mu: 0.5, preload: 150}
excitation:
  - {body: beam1, node_set: FORCE1, direction: z, amplitude: 50}
analysis:
  frequency: {start_hz: 1852, stop_hz: 1856, step_hz: 0.01}
)";

}  // namespace stickslip::testing_cases
