#include "model/campbell.h"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

#include "core/errors.h"
#include "core/types.h"
#include "linalg/modal.h"
#include "model/cyclic_modes.h"

namespace stickslip {

double signed_frequency_hz(double omega2) {
  const double f = std::sqrt(std::abs(omega2)) / (2 * kPi);
  return omega2 < 0 ? -f : f;
}

namespace {

// The line of (system, h, mode), made when first met.
CampbellLine& line_of(CampbellDiagram& d, const std::string& system, int h, int mode) {
  for (CampbellLine& l : d.lines) {
    if (l.system == system && l.nodal_diameter == h && l.mode == mode) return l;
  }
  d.lines.push_back({system, h, mode, {}});
  return d.lines.back();
}

void add_eigenvalues(CampbellDiagram& d, const std::string& system, int h,
                     const Eigen::VectorXd& omega2, int num_modes, size_t speed) {
  const int n = std::min<int>(num_modes, static_cast<int>(omega2.size()));
  for (int j = 0; j < n; ++j) {
    CampbellLine& l = line_of(d, system, h, j + 1);
    // A speed at which the line has no mode (fewer modes there) keeps NaN.
    l.frequencies_hz.resize(d.speeds_rpm.size(), std::nan(""));
    l.frequencies_hz[speed] = signed_frequency_hz(omega2(j));
  }
}

}  // namespace

CampbellDiagram campbell_diagram(const CaseDefinition& def, int num_modes,
                                 const ProgressFn& progress, ModelCache* cache) {
  if (!def.rotation || def.rotation->campbell_speeds_rpm.empty()) {
    throw InvalidInput(def.where("rotation"),
                       "the Campbell diagram needs rotation.campbell.speeds_rpm");
  }
  require(num_modes >= 1, "num_modes", std::to_string(num_modes), ">= 1");
  CampbellDiagram d;
  d.speeds_rpm = def.rotation->campbell_speeds_rpm;
  d.engine_orders = def.rotation->engine_orders;
  const bool cyclic = std::any_of(def.bodies.begin(), def.bodies.end(),
                                  [](const auto& b) { return b.second.cyclic.has_value(); });
  for (size_t s = 0; s < d.speeds_rpm.size(); ++s) {
    CaseDefinition at = def;
    at.rotation->speed_rpm = d.speeds_rpm[s];
    if (progress) progress(fmt::format("Campbell diagram: {} rpm", d.speeds_rpm[s]));
    if (cyclic) {
      const CyclicModes modes = cyclic_modes(at, num_modes, progress, cache);
      for (const NodalDiameterModes& m : modes.diameters) {
        if (!m.summary.ok()) {
          throw InvalidInput(def.where("rotation.campbell.speeds_rpm"),
                             fmt::format("the modes of nodal diameter {} at {} rpm failed: {}",
                                         m.nodal_diameter, d.speeds_rpm[s], m.summary.message));
        }
        // cyclic_modes gives frequencies (Hz, from ω² ≥ 0); back to ω² for the sign rule.
        const Eigen::VectorXd omega2 =
            (2 * kPi * m.frequencies_hz).cwiseProduct(2 * kPi * m.frequencies_hz);
        add_eigenvalues(d, "free", m.nodal_diameter, omega2, num_modes, s);
      }
      continue;
    }
    const PreparedModel model = prepare_model(at, progress, cache);
    const ModalResult free = dense_modes(model.K, model.M);
    if (!free.summary.ok()) {
      throw InvalidInput(def.where("bodies"), "the reduced mass matrix is not positive definite");
    }
    add_eigenvalues(d, "free", -1, free.eigenvalues, num_modes, s);
    if (!model.pairs.empty()) {
      add_eigenvalues(d, "stuck", -1, stuck_modes(model, at).eigenvalues, num_modes, s);
    }
  }
  for (CampbellLine& l : d.lines) l.frequencies_hz.resize(d.speeds_rpm.size(), std::nan(""));
  // Stuck lines first (the system the forced response starts from), then free; by h, mode.
  std::stable_sort(d.lines.begin(), d.lines.end(),
                   [](const CampbellLine& a, const CampbellLine& b) {
                     if (a.system != b.system) return a.system == "stuck";
                     if (a.nodal_diameter != b.nodal_diameter)
                       return a.nodal_diameter < b.nodal_diameter;
                     return a.mode < b.mode;
                   });
  return d;
}

}  // namespace stickslip
