// Argument wrappers that give the bindings readable signatures and their own errors.
//
// The bindings take NumPy-like arguments as raw Python objects so that numpy_convert.cpp can
// validate them with messages that name the argument (a plain Eigen or array_t parameter would
// reject a bad value with pybind11's generic "incompatible function arguments" TypeError).
// A raw py::handle parameter shows up as `handle` in help(), though. These wrappers accept
// any object, exactly like py::handle, but carry the type a caller should pass, so that
// help(edgedeform.Deformer.solve) reads `targets: numpy.ndarray[float64[h, 3]]`.
#pragma once

#include <pybind11/pybind11.h>

namespace edgedeform::bindings {

namespace py = pybind11;

// One wrapper per documented argument kind; `obj` is the caller's object, unconverted.
struct PointsArg { py::handle obj; };          // (n, 3) floats: positions of every vertex
struct TargetsArg { py::handle obj; };         // (h, 3) floats: one row per handle
struct FacesArg { py::handle obj; };           // (m, 3) integers
struct IndicesArg { py::handle obj; };         // (k,) integers
struct OptionalIndicesArg { py::handle obj; }; // (k,) integers, or None
struct OptionalPointsArg { py::handle obj; };  // (n, 3) floats, or None
struct OptionalTargetsArg { py::handle obj; }; // (h, 3) floats, or None
struct StiffnessArg { py::handle obj; };       // a float, or (n,) floats
// Scalars, converted by scalar_convert.h (a wrong type is a short TypeError naming the argument)
struct IntArg { py::handle obj; };
struct FloatArg { py::handle obj; };
struct OptionalFloatArg { py::handle obj; };
struct BoolArg { py::handle obj; };
struct StrArg { py::handle obj; };

}  // namespace edgedeform::bindings

namespace pybind11::detail {

// Accepts every object; validation happens later, with the argument's name, in numpy_convert.
#define EDGEDEFORM_ANY_OBJECT_CASTER(Type, doc_name)                                              \
  template <>                                                                                    \
  struct type_caster<edgedeform::bindings::Type> {                                              \
    PYBIND11_TYPE_CASTER(edgedeform::bindings::Type, const_name(doc_name));                     \
    bool load(handle src, bool) {                                                                \
      value.obj = src;                                                                           \
      return true;                                                                               \
    }                                                                                            \
    static handle cast(const edgedeform::bindings::Type& v, return_value_policy, handle) {     \
      return v.obj.inc_ref();                                                                    \
    }                                                                                            \
  }

EDGEDEFORM_ANY_OBJECT_CASTER(PointsArg, "numpy.ndarray[float64[n, 3]]");
EDGEDEFORM_ANY_OBJECT_CASTER(TargetsArg, "numpy.ndarray[float64[h, 3]]");
EDGEDEFORM_ANY_OBJECT_CASTER(FacesArg, "numpy.ndarray[int[m, 3]]");
EDGEDEFORM_ANY_OBJECT_CASTER(IndicesArg, "numpy.ndarray[int[k]]");
EDGEDEFORM_ANY_OBJECT_CASTER(OptionalIndicesArg, "Optional[numpy.ndarray[int[k]]]");
EDGEDEFORM_ANY_OBJECT_CASTER(OptionalPointsArg, "Optional[numpy.ndarray[float64[n, 3]]]");
EDGEDEFORM_ANY_OBJECT_CASTER(OptionalTargetsArg, "Optional[numpy.ndarray[float64[h, 3]]]");
EDGEDEFORM_ANY_OBJECT_CASTER(StiffnessArg, "Union[float, numpy.ndarray[float64[n]]]");
EDGEDEFORM_ANY_OBJECT_CASTER(IntArg, "int");
EDGEDEFORM_ANY_OBJECT_CASTER(FloatArg, "float");
EDGEDEFORM_ANY_OBJECT_CASTER(OptionalFloatArg, "Optional[float]");
EDGEDEFORM_ANY_OBJECT_CASTER(BoolArg, "bool");
EDGEDEFORM_ANY_OBJECT_CASTER(StrArg, "str");

#undef EDGEDEFORM_ANY_OBJECT_CASTER

}  // namespace pybind11::detail
