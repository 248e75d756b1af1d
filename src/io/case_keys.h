// The table of every key of the case file (docs/case-file.md is its long form): where the key
// lives, its type and rule, its unit, its default, whether a study may vary it, and a line of help.
// It drives
//   - the parser's known keys of each map (io/case_file.cpp: an unknown key is an error that lists
//     them),
//   - the keys a study accepts (`study.parameter`, with_parameter), and the message listing them,
//   - `stickslip keys`, which prints it,
// and tests check that docs/case-file.md documents exactly these keys, each with the same default.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace stickslip {

struct CaseKey {
  // The map the key belongs to, spelled as docs/case-file.md's headings: "" (top level),
  // "analysis", "analysis.frequency", "materials.NAME" (NAME: a name the case chooses),
  // "contacts[]" (an entry of a list), "bodies.NAME.supports" (its entries), ...
  std::string_view section;
  std::string_view key;            // "youngs_modulus"; "total.split" is `split` inside `total`
  std::string_view type;           // type and rule, as the docs write it
  std::string_view unit;           // SI unit, or empty
  std::string_view default_value;  // as the docs' default column: `64`, required, none, ...
  bool study = false;              // a study may vary it (per_pair / total: each numeric parameter)
  std::string_view help;           // one line
};

// Every key, in the order of docs/case-file.md.
const std::vector<CaseKey>& case_keys();
// The names of the keys directly in `section` (dotted keys such as "total.split" excluded), in
// table order; empty for a section the table does not have.
std::vector<std::string> case_keys_in(std::string_view section);
// The keys a study can vary, as study.parameter paths: "materials.NAME.youngs_modulus",
// "contacts.NAME.per_pair.<parameter>", "excitation[i].amplitude", ... (lists by 0-based index,
// contacts by name).
std::vector<std::string> study_parameter_paths();

}  // namespace stickslip
