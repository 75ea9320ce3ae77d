#include "base/types.h"

#include <stdexcept>

namespace edgedeform {

const char* domain_name(Domain domain) { return domain == Domain::Edge ? "edge" : "primal"; }

Domain parse_domain(const std::string& name) {
  if (name == "edge") return Domain::Edge;
  if (name == "primal") return Domain::Primal;
  throw std::invalid_argument("domain must be \"edge\" or \"primal\", got \"" + name + "\"");
}

}  // namespace edgedeform
