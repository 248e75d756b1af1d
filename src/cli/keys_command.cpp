// `stickslip keys [SECTION]`: the case file's keys from io/case_keys.h, one line each.
#include <algorithm>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "cli/commands.h"
#include "core/errors.h"
#include "io/case_keys.h"

namespace stickslip {
namespace {

std::string without_backquotes(std::string_view text) {
  std::string out;
  for (char c : text)
    if (c != '`') out += c;
  return out;
}

std::string full_path(const CaseKey& k) {
  return k.section.empty() ? std::string(k.key) : std::string(k.section) + "." + std::string(k.key);
}

}  // namespace

int run_keys(const KeysCommand& command) {
  std::vector<const CaseKey*> shown;
  for (const CaseKey& k : case_keys()) {
    const std::string path = full_path(k);
    if (command.section.empty() || path == command.section ||
        path.rfind(command.section + ".", 0) == 0)
      shown.push_back(&k);
  }
  if (shown.empty()) {
    std::vector<std::string> sections;
    for (const CaseKey& k : case_keys()) {
      if (!k.section.empty() &&
          std::find(sections.begin(), sections.end(), k.section) == sections.end())
        sections.emplace_back(k.section);
    }
    std::string list;
    for (const std::string& s : sections) list += (list.empty() ? "" : ", ") + s;
    throw InvalidInput({"", 0, "section"},
                       "no key in '" + command.section + "'; the sections are " + list);
  }
  size_t width = 0;
  for (const CaseKey* k : shown) width = std::max(width, full_path(*k).size());
  for (const CaseKey* k : shown) {
    std::string line = fmt::format("{:<{}}  {}", full_path(*k), width, without_backquotes(k->type));
    if (!k->unit.empty() && k->unit != "–") line += fmt::format(" ({})", k->unit);
    if (!k->default_value.empty() && k->default_value != "–")
      line += "; default " + without_backquotes(k->default_value);
    if (k->study) line += "; a study may vary it";
    if (!k->help.empty()) line += "\n" + std::string(width + 2, ' ') + without_backquotes(k->help);
    fmt::print("{}\n", line);
  }
  fmt::print("({} keys; docs/case-file.md explains each)\n", shown.size());
  return 0;
}

}  // namespace stickslip
