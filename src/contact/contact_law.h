// The registry of contact laws: what the case-file parser accepts under `contacts[].law` and what
// the model builder makes of it. A new law is one register_contact_law() call (before the case
// file is read); nothing else names laws.
//
// A law acts either in a frame (uses_frame: rows t1, t2, n of the contact's `normal`/`t1`, 3
// rows) or along one `direction` (1 row). A name may be registered twice, once of each kind (the
// built-in `linear`: one spring k along a direction, or springs kt, kt, kn in a frame); the case
// file then picks the variant by the keys it gives (`normal`/`t1` or a key only the frame variant
// has: the frame variant; `direction` or a key only the other has: the 1D one).
//
// Parameters are numbers by key (SI units), given per pair or as totals over a contact's pairs;
// `split` keys are divided among the pairs with `total:` (stiffnesses, forces), the others not
// (μ). The values a law's functions receive hold its parameter keys, with `preload` the pair's
// resolved N0 when the law has_preload (0 when the preload is computed or a gap is given), and
// `gap` (g0, m) when the law has_gap.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "contact/nonlinear_element.h"

namespace stickslip {

using LawValues = std::map<std::string, double>;  // key -> value, SI units

struct LawParameter {
  enum class Rule { kPositive, kNonNegative, kAny };
  std::string key;                // e.g. "kt"
  Rule rule = Rule::kPositive;    // checked where the case file is read
  bool required = true;           // the case file must give it
  bool split = true;              // divided among the pairs of a `total:` block
};

struct ContactLaw {
  std::string name;       // the case file's `law`, e.g. "friction"
  bool uses_frame = false;  // 3 rows (t1, t2, n) in the frame normal/t1; else 1 row along direction
  std::vector<LawParameter> parameters;  // the keys of per_pair / total, in their order
  bool has_preload = false;              // a `preload` (N0) key and `preload_file`
  bool can_compute_preload = false;      // `preload: computed` (the static contact problem)
  bool has_gap = false;                  // `gap` (g0) instead of a preload
  // Stiffness of the element's rows when stuck (the tangent at rest), N/m: the stuck assembly's
  // springs (modes of the stuck assembly, `around_mode`, the stuck initial guess).
  std::function<Eigen::VectorXd(const LawValues&)> stuck_stiffness;
  // The element of one pair (InvalidInput for values it refuses).
  std::function<ElementPtr(const LawValues&)> make_element;

  const LawParameter* parameter(const std::string& key) const;  // nullptr if not a key of it
  std::vector<std::string> parameter_keys() const;
  std::vector<std::string> required_keys() const;
};

// Adds a law (InvalidInput when its name is registered already with the same uses_frame, when it
// lacks a name, a parameter, stuck_stiffness or make_element, or when has_preload and no parameter
// `preload`). The built-in laws friction, jenkins, gap, cubic and linear (1D and frame) are there
// from the start.
void register_contact_law(ContactLaw law);

// The variants registered under `name` (one or two; empty for an unknown name).
std::vector<const ContactLaw*> find_contact_laws(const std::string& name);
// The variant of `name` with this uses_frame (InvalidInput naming the law when there is none).
const ContactLaw& contact_law(const std::string& name, bool uses_frame);
// Every registered name, sorted, each once.
std::vector<std::string> contact_law_names();
// The rule of a parameter key in the first law that has it (false when no law has it).
bool contact_parameter_rule(const std::string& key, LawParameter::Rule* rule);

}  // namespace stickslip
