// What this build was made with.
#pragma once

#include <string>

namespace edgedeform {

const char* version();
const char* solver_backend();  // "cholmod-supernodal" | "eigen-simplicial-ldlt"
bool has_openmp();
int max_threads();
std::string eigen_version();
std::string compiler();

}  // namespace edgedeform
