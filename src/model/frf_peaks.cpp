#include "model/frf_peaks.h"

#include <cmath>

#include "core/types.h"

namespace stickslip {

std::vector<FrfPeak> frf_peaks(const CaseDefinition& def, const PreparedModel& model,
                               const FrequencyResponse& fr) {
  std::vector<FrfPeak> peaks;
  int first = -1, last = -1;
  for (size_t i = 0; i < fr.points.size(); ++i) {
    if (!fr.points[i].converged) continue;
    if (first < 0) first = static_cast<int>(i);
    last = static_cast<int>(i);
  }
  for (const ResponseDofDefinition& r : def.output.frf) {
    FrfPeak peak;
    peak.dof = r;
    const int b = model.body_index(r.body);
    const int g = b < 0 ? -1 : model.bodies[b].global_dof(r.node, r.direction);
    for (size_t i = 0; i < fr.points.size() && g >= 0; ++i) {
      const FrequencyPoint& p = fr.points[i];
      if (!p.converged) continue;
      const int h = p.master.cols() > 1 ? 1 : 0;  // harmonic 1 (column 0 is the mean)
      const double a = std::abs(p.master(g, h));
      if (peak.point < 0 || a > peak.amplitude_m) {
        peak.point = static_cast<int>(i);
        peak.amplitude_m = a;
        peak.frequency_hz = rad_s_to_hz(p.omega);
      }
    }
    peak.at_edge = peak.point >= 0 && (peak.point == first || peak.point == last);
    // A continuation locates the peak between its points (frequency_response.h, PeakOptions).
    peak.message = "the largest amplitude of the points";
    for (const ResponsePeak& located : fr.peaks) {
      if (g < 0 || located.dof != g || located.sampled_point != peak.point) continue;
      peak.message = located.message;
      if (!located.located) continue;
      peak.located = true;
      peak.amplitude_m = located.amplitude;
      peak.frequency_hz = rad_s_to_hz(located.omega);
    }
    peaks.push_back(peak);
  }
  return peaks;
}

}  // namespace stickslip
