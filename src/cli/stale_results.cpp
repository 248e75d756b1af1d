#include "cli/stale_results.h"

#include <algorithm>
#include <regex>
#include <set>
#include <system_error>

#include "io/atomic_file.h"

namespace stickslip {

namespace fs = std::filesystem;

bool is_result_name(const std::string& relative, ResultFamily family) {
  static const std::regex recovery(
      "recovery_check\\.csv|recovered_nodes\\.csv|recovery\\.pvd|recovery_p[0-9]+\\.vtm|"
      "recovery_envelope\\.vtm|recovery/[^/]+/(p[0-9]+|envelope)\\.vtu|"
      "recovery_p[0-9]+_[^/]+\\.vtu|recovery_envelope_[^/]+\\.vtu|"
      "frf_full_vs_reduced\\.(png|svg|dat|gp)");
  static const std::regex everything(
      "(points|master_response|contact_forces|contact_state|contact_coupling|histories|"
      "nonlinear_modes|nonlinear_mode_shapes|snmt|snmt_response)\\.csv|"
      "summary\\.json|"
      "(frf|frf_phase|contact_state|dissipation|hysteresis|hysteresis_t2|"
      "nonlinear_mode_backbone|nonlinear_mode_damping|nonlinear_mode_contact_state)\\.(png|svg|dat|"
      "gp)|"
      "contact_map\\.vtu|loads_p[0-9]+_[^/]+\\.mac|"
      "recovery_p[0-9]+_[^/]+\\.inp");
  if (std::regex_match(relative, recovery)) return true;
  return family == ResultFamily::kEverything && std::regex_match(relative, everything);
}

std::vector<std::string> remove_stale_results(const fs::path& dir, ResultFamily family) {
  std::set<std::string> keep;
  for (const fs::path& f : published_files_under(dir)) keep.insert(f.generic_string());
  std::vector<std::string> removed;
  std::error_code ec;
  // The folder itself and recovery/<body>/: nothing else is looked into.
  std::vector<fs::path> candidates;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.is_regular_file(ec)) candidates.push_back(e.path().filename());
  }
  std::vector<fs::path> body_folders;
  for (const auto& e : fs::directory_iterator(dir / "recovery", ec)) {
    if (!e.is_directory(ec)) continue;
    body_folders.push_back(e.path());
    for (const auto& f : fs::directory_iterator(e.path(), ec)) {
      if (f.is_regular_file(ec)) candidates.push_back(fs::relative(f.path(), dir, ec));
    }
  }
  for (const fs::path& relative : candidates) {
    const std::string name = relative.generic_string();
    if (keep.count(name) || !is_result_name(name, family)) continue;
    if (fs::remove(dir / relative, ec) && !ec) removed.push_back(name);
  }
  for (const fs::path& folder : body_folders) {
    if (fs::is_empty(folder, ec) && !ec) fs::remove(folder, ec);
  }
  if (fs::is_directory(dir / "recovery", ec) && fs::is_empty(dir / "recovery", ec) && !ec) {
    fs::remove(dir / "recovery", ec);
  }
  std::sort(removed.begin(), removed.end());
  return removed;
}

}  // namespace stickslip
