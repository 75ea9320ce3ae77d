#include "scalar_convert.h"

#include <stdexcept>

namespace edgedeform::bindings {

namespace {

[[noreturn]] void wrong_type(const py::handle& obj, const char* name, const char* expected) {
  throw py::type_error(std::string(name) + " must be " + expected + ", got " + Py_TYPE(obj.ptr())->tp_name);
}

bool is_bool(const py::handle& obj) {
  // numpy.bool_ (NumPy 1) or numpy.bool (NumPy 2) is no subclass of bool
  return PyBool_Check(obj.ptr()) || std::string(Py_TYPE(obj.ptr())->tp_name).rfind("numpy.bool", 0) == 0;
}

// A float, an int or what converts like one (numpy.float32), but no bool and no str.
bool is_number(const py::handle& obj) {
  const PyNumberMethods* number = Py_TYPE(obj.ptr())->tp_as_number;
  return !is_bool(obj) && (PyFloat_Check(obj.ptr()) || PyIndex_Check(obj.ptr()) || (number && number->nb_float));
}

double as_double(const py::handle& obj) {
  const double v = PyFloat_AsDouble(obj.ptr());
  if (v == -1.0 && PyErr_Occurred()) throw py::error_already_set();  // e.g. an int beyond a double
  return v;
}

// The integer as written, for the message ("100000000000000000000").
std::string int_text(const py::handle& value) {
  try {
    return py::str(value);
  } catch (const py::error_already_set&) {  // more digits than int -> str allows
    return "an integer of more than 4300 digits";
  }
}

}  // namespace

int to_int(const py::handle& obj, const IntRange& range) {
  if (is_bool(obj) || !PyIndex_Check(obj.ptr())) wrong_type(obj, range.name, "an int");
  const py::object value = py::reinterpret_steal<py::object>(PyNumber_Index(obj.ptr()));
  if (!value) throw py::error_already_set();
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
  if (overflow != 0 || v < range.low || v > range.high)
    throw std::invalid_argument(out_of_range_message(range, int_text(value)));
  return static_cast<int>(v);
}

double to_float(const py::handle& obj, const char* name) {
  if (!is_number(obj)) wrong_type(obj, name, "a float");
  return as_double(obj);
}

std::optional<double> to_optional_float(const py::handle& obj, const char* name) {
  if (obj.is_none()) return std::nullopt;
  if (!is_number(obj)) wrong_type(obj, name, "a float or None");
  return as_double(obj);
}

bool to_bool(const py::handle& obj, const char* name) {
  if (!is_bool(obj)) wrong_type(obj, name, "a bool");
  return PyObject_IsTrue(obj.ptr()) == 1;
}

std::string to_str(const py::handle& obj, const char* name) {
  if (!PyUnicode_Check(obj.ptr())) wrong_type(obj, name, "a str");
  return obj.cast<std::string>();
}

}  // namespace edgedeform::bindings
