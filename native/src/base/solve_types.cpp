#include "base/solve_types.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace edgedeform {

const char* acceleration_name(Acceleration a) {
  switch (a) {
    case Acceleration::Automatic: return "auto";
    case Acceleration::Lbfgs: return "lbfgs";
    case Acceleration::Anderson: return "anderson";
    case Acceleration::None: break;
  }
  return "none";
}

Acceleration parse_acceleration(const std::string& name) {
  for (Acceleration a : {Acceleration::Automatic, Acceleration::Lbfgs, Acceleration::Anderson, Acceleration::None})
    if (name == acceleration_name(a)) return a;
  throw std::invalid_argument("acceleration must be \"auto\", \"lbfgs\", \"anderson\" or \"none\", got \"" + name + "\"");
}

std::string out_of_range_message(const IntRange& range, const std::string& value) {
  return std::string(range.name) + " must be an integer in [" + std::to_string(range.low) + ", " +
         std::to_string(range.high) + "], got " + value;
}

void check_in_range(const IntRange& range, int value) {
  if (value < range.low || value > range.high)
    throw std::invalid_argument(out_of_range_message(range, std::to_string(value)));
}

std::string not_converged_warning(int max_iterations, double distance_estimate, double tolerance,
                                  const std::string& estimate_is, const std::string& unknown_because) {
  std::ostringstream msg;
  msg << "not converged: stopped at max_iterations (" << max_iterations << "); ";
  if (std::isfinite(distance_estimate)) {
    msg << estimate_is << " " << distance_estimate << " of the bounding-box diagonal (tolerance " << tolerance << ")";
  } else {
    msg << "the distance to the fixed point is unknown";
    if (!unknown_because.empty()) msg << ": " << unknown_because;
    msg << " (tolerance " << tolerance << " of the bounding-box diagonal)";
  }
  return msg.str();
}

}  // namespace edgedeform
