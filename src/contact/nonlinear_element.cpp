#include "contact/nonlinear_element.h"

#include <cmath>
#include <string>

#include "core/errors.h"
#include "core/format.h"

namespace stickslip {

void validate(const MarchOptions& options) {
  require(std::isfinite(options.tolerance) && options.tolerance > 0.0, "MarchOptions.tolerance",
          format_number(options.tolerance), "> 0");
  require(options.max_periods >= 2, "MarchOptions.max_periods", std::to_string(options.max_periods),
          ">= 2");
}

}  // namespace stickslip
