#include "contact/contact_law.h"

#include <algorithm>
#include <memory>
#include <mutex>
#include <set>
#include <utility>

#include "contact/friction_contact.h"
#include "contact/linear_springs.h"
#include "contact/springs.h"
#include "core/errors.h"

namespace stickslip {
namespace {

using Rule = LawParameter::Rule;

double value(const LawValues& v, const std::string& key) {
  const auto it = v.find(key);
  return it == v.end() ? 0.0 : it->second;
}

std::vector<ContactLaw> built_in_laws() {
  std::vector<ContactLaw> laws;
  {
    ContactLaw l;
    l.name = "friction";
    l.uses_frame = true;
    l.parameters = {{"kt"}, {"kn"}, {"mu", Rule::kNonNegative, true, false},
                    {"preload", Rule::kNonNegative, false}};
    l.has_preload = l.can_compute_preload = l.has_gap = true;
    l.stuck_stiffness = [](const LawValues& v) {
      return Eigen::VectorXd(Eigen::Vector3d(value(v, "kt"), value(v, "kt"), value(v, "kn")));
    };
    l.make_element = [](const LawValues& v) -> ElementPtr {
      return std::make_shared<FrictionContact3D>(FrictionContactParameters{
          value(v, "kt"), value(v, "kn"), value(v, "mu"), value(v, "preload"), value(v, "gap")});
    };
    laws.push_back(std::move(l));
  }
  {
    ContactLaw l;
    l.name = "jenkins";
    l.parameters = {{"kt"}, {"mu", Rule::kNonNegative, true, false},
                    {"preload", Rule::kNonNegative, false}};
    l.has_preload = true;
    l.stuck_stiffness = [](const LawValues& v) {
      return Eigen::VectorXd::Constant(1, value(v, "kt")).eval();
    };
    l.make_element = [](const LawValues& v) -> ElementPtr {
      return std::make_shared<Jenkins1D>(
          JenkinsParameters{value(v, "kt"), value(v, "mu"), value(v, "preload")});
    };
    laws.push_back(std::move(l));
  }
  {
    ContactLaw l;
    l.name = "gap";
    l.parameters = {{"kn"}, {"preload", Rule::kNonNegative, false}};
    l.has_preload = l.can_compute_preload = l.has_gap = true;
    l.stuck_stiffness = [](const LawValues& v) {
      return Eigen::VectorXd::Constant(1, value(v, "kn")).eval();
    };
    l.make_element = [](const LawValues& v) -> ElementPtr {
      return std::make_shared<UnilateralSpring>(
          UnilateralSpringParameters{value(v, "kn"), value(v, "gap"), value(v, "preload")});
    };
    laws.push_back(std::move(l));
  }
  {
    ContactLaw l;
    l.name = "cubic";
    l.parameters = {{"k1", Rule::kNonNegative}, {"k3", Rule::kAny}};
    l.stuck_stiffness = [](const LawValues& v) {  // the tangent at rest
      return Eigen::VectorXd::Constant(1, value(v, "k1")).eval();
    };
    l.make_element = [](const LawValues& v) -> ElementPtr {
      return std::make_shared<CubicSpring>(CubicSpringParameters{value(v, "k1"), value(v, "k3")});
    };
    laws.push_back(std::move(l));
  }
  {
    ContactLaw l;  // one spring k along a direction: a cubic spring without its cubic term
    l.name = "linear";
    l.parameters = {{"k"}};
    l.stuck_stiffness = [](const LawValues& v) {
      return Eigen::VectorXd::Constant(1, value(v, "k")).eval();
    };
    l.make_element = [](const LawValues& v) -> ElementPtr {
      return std::make_shared<CubicSpring>(CubicSpringParameters{value(v, "k"), 0.0});
    };
    laws.push_back(std::move(l));
  }
  {
    ContactLaw l;  // springs (kt, kt, kn) in the frame: a stuck friction contact
    l.name = "linear";
    l.uses_frame = true;
    l.parameters = {{"kt"}, {"kn"}};
    l.stuck_stiffness = [](const LawValues& v) {
      return Eigen::VectorXd(Eigen::Vector3d(value(v, "kt"), value(v, "kt"), value(v, "kn")));
    };
    l.make_element = [](const LawValues& v) -> ElementPtr {
      return make_linear_springs(
          Eigen::Vector3d(value(v, "kt"), value(v, "kt"), value(v, "kn")));
    };
    laws.push_back(std::move(l));
  }
  return laws;
}

// The laws, built-in ones first; deque-like stability: entries are never removed, and pointers
// handed out stay valid because each law is held by a unique_ptr.
struct Registry {
  std::mutex mutex;
  std::vector<std::unique_ptr<const ContactLaw>> laws;
  Registry() {
    for (ContactLaw& l : built_in_laws()) laws.push_back(std::make_unique<ContactLaw>(std::move(l)));
  }
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

const LawParameter* ContactLaw::parameter(const std::string& key) const {
  for (const LawParameter& p : parameters) {
    if (p.key == key) return &p;
  }
  return nullptr;
}

std::vector<std::string> ContactLaw::parameter_keys() const {
  std::vector<std::string> keys;
  for (const LawParameter& p : parameters) keys.push_back(p.key);
  return keys;
}

std::vector<std::string> ContactLaw::required_keys() const {
  std::vector<std::string> keys;
  for (const LawParameter& p : parameters) {
    if (p.required) keys.push_back(p.key);
  }
  return keys;
}

void register_contact_law(ContactLaw law) {
  if (law.name.empty()) throw InvalidInput("register_contact_law: a law needs a name");
  const std::string what = "register_contact_law: law " + law.name;
  if (law.parameters.empty()) throw InvalidInput(what + " has no parameters");
  if (!law.stuck_stiffness || !law.make_element) {
    throw InvalidInput(what + " needs stuck_stiffness and make_element");
  }
  if (law.has_preload && law.parameter("preload") == nullptr) {
    throw InvalidInput(what + " has a preload but no parameter 'preload'");
  }
  if (law.can_compute_preload && !law.has_preload) {
    throw InvalidInput(what + " computes a preload it does not have");
  }
  std::set<std::string> keys;
  for (const LawParameter& p : law.parameters) {
    if (p.key.empty() || !keys.insert(p.key).second) {
      throw InvalidInput(what + ": parameter keys must be non-empty and distinct");
    }
  }
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& l : r.laws) {
    if (l->name == law.name && l->uses_frame == law.uses_frame) {
      throw InvalidInput(what + " is registered already");
    }
  }
  r.laws.push_back(std::make_unique<ContactLaw>(std::move(law)));
}

std::vector<const ContactLaw*> find_contact_laws(const std::string& name) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<const ContactLaw*> out;
  for (const auto& l : r.laws) {
    if (l->name == name) out.push_back(l.get());
  }
  return out;
}

const ContactLaw& contact_law(const std::string& name, bool uses_frame) {
  for (const ContactLaw* l : find_contact_laws(name)) {
    if (l->uses_frame == uses_frame) return *l;
  }
  throw InvalidInput("unknown contact law " + name + (uses_frame ? " (in a frame)" : " (1D)"));
}

std::vector<std::string> contact_law_names() {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  std::set<std::string> names;
  for (const auto& l : r.laws) names.insert(l->name);
  return {names.begin(), names.end()};
}

bool contact_parameter_rule(const std::string& key, LawParameter::Rule* rule) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& l : r.laws) {
    if (const LawParameter* p = l->parameter(key)) {
      *rule = p->rule;
      return true;
    }
  }
  return false;
}

}  // namespace stickslip
