// Python scalars -> C++ with errors that name the argument: TypeError "NAME must be TYPE, got
// TYPENAME" (never pybind11's "incompatible function arguments", which prints every argument,
// arrays included: 3,000 characters for a str roi_radius), ValueError for an integer outside
// its range. The bindings take these arguments as the typed_args.h wrappers (any object) and
// convert them here.
#pragma once

#include <optional>
#include <string>

#include <pybind11/pybind11.h>

#include "base/solve_types.h"

namespace edgedeform::bindings {

namespace py = pybind11;

// An int (or anything with __index__, such as numpy.int64; not a bool) inside `range`.
int to_int(const py::handle& obj, const IntRange& range);
// A float or int (not a bool, not a str).
double to_float(const py::handle& obj, const char* name);
// None, or a float as to_float.
std::optional<double> to_optional_float(const py::handle& obj, const char* name);
// True or False (numpy.bool_ too).
bool to_bool(const py::handle& obj, const char* name);
std::string to_str(const py::handle& obj, const char* name);

}  // namespace edgedeform::bindings
