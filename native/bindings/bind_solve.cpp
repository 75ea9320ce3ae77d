// Deformer.solve and the module's SOLVE_DEFAULTS and ACCELERATIONS, all made from the two
// tables below: solve()'s parameters with their types, defaults (SolveOptions{}) and help
// text, and the acceleration methods. A new SolveOptions field or method is one line in a
// table; help(), the defaults the command line, the add-on and the docs read
// (docs/decisions/0050-one-source-for-solve-options.md) and the argument checks follow.
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "edgedeform/deformer.h"
#include "edgedeform/errors.h"
#include "gil.h"
#include "numpy_convert.h"
#include "scalar_convert.h"
#include "signal_check.h"
#include "typed_args.h"

namespace edgedeform::bindings {

namespace {

// A field of SolveOptions (or of an options struct inside it: OPTION(newton.lead_in)).
#define OPTION(path) [](auto& o) -> auto& { return o.path; }

// solve()'s keyword arguments after `targets`, in the order of its positional parameters.
template <class Visit>
void visit_solve_options(Visit&& option) {
  option("max_iterations", OPTION(max_iterations), "most local/global iterations in this call.");
  option("tolerance", OPTION(tolerance),
         "stop when the estimated largest vertex distance to the fixed point is below tolerance "
         "times the rest bounding-box diagonal; then result.converged is True.");
  option("warm_start", OPTION(warm_start),
         "start from the previous solve's shape; with unchanged targets this continues the same "
         "iteration (Anderson history included), so repeated short calls settle on the cold "
         "solve's shape.");
  option("initial", OPTION(initial), "(n, 3) positions to start from instead (a local step on them first), or None.");
  option("acceleration", OPTION(acceleration),
         "how the fixed point is reached; each method ends at a fixed point of the same map (where "
         "the energy has several near one another, methods can end at different ones):");
  option("anderson_window", OPTION(anderson_window), "how many past iterates Anderson acceleration combines (1..50).");
  option("verify_claims", OPTION(verify_claims),
         "plain/Anderson: before claiming convergence, estimate J_G's largest modulus by 30 "
         "Arnoldi steps at the point (each a back-substitution) and claim only if the distance "
         "bound with it holds too (a secant estimate can miss a slow mode).");
  option("newton", OPTION(newton), "the Newton method's settings, a NewtonOptions (None: its defaults).");
}

#undef OPTION

// The methods `acceleration` takes, in the order help() and ACCELERATIONS list them.
struct Method {
  Acceleration value;
  const char* doc;
};
const Method kMethods[] = {
    {Acceleration::Newton, "an Anderson lead-in, then projected Newton steps, each a sparse factorization of the "
                           "Newton matrix (settings in `newton`)"},
    {Acceleration::Anderson, "Anderson-accelerated local/global"},
    {Acceleration::None, "the plain local/global method"},
};

// How each field type meets Python: its name in help(), its default as a Python object, and
// the conversion of an argument (TypeError naming the argument when it has another type).
template <class T>
T cast_argument(const py::handle& value, const char* name, const std::string& type) {
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw py::type_error(std::string("solve(): ") + name + " must be " + type + ", got " +
                         std::string(py::str(py::type::handle_of(value).attr("__name__"))));
  }
}

// An options struct inside SolveOptions, bound as a Python class (NewtonOptions): None stands
// for its defaults, and is what SOLVE_DEFAULTS and help() show.
template <class T>
struct Codec {
  static std::string type() {
    const py::handle cls = py::type::of<T>();
    return "Optional[" + std::string(py::str(cls.attr("__module__"))) + "." +
           std::string(py::str(cls.attr("__qualname__"))) + "]";
  }
  static py::object to_python(const T&) { return py::none(); }
  static T from_python(const py::handle& h, const char* name) {
    if (h.is_none()) return T{};
    return cast_argument<T>(h, name, "a " + std::string(py::str(py::type::of<T>().attr("__name__"))) + " or None");
  }
};

template <>
struct Codec<int> {
  static std::string type() { return "int"; }
  static py::object to_python(int v) { return py::int_(v); }
  static int from_python(const py::handle& h, const char* name) {
    for (const IntRange& range : {kMaxIterationsRange, kAndersonWindowRange})
      if (std::string(name) == range.name) return to_int(h, range);
    return to_int(h, IntRange{name, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()});
  }
};
template <>
struct Codec<double> {
  static std::string type() { return "float"; }
  static py::object to_python(double v) { return py::float_(v); }
  static double from_python(const py::handle& h, const char* name) { return to_float(h, name); }
};
template <>
struct Codec<bool> {
  static std::string type() { return "bool"; }
  static py::object to_python(bool v) { return py::bool_(v); }
  static bool from_python(const py::handle& h, const char* name) { return to_bool(h, name); }
};
template <>
struct Codec<Acceleration> {
  static std::string type() { return "str"; }
  static py::object to_python(Acceleration v) { return py::str(acceleration_name(v)); }
  static Acceleration from_python(const py::handle& h, const char* name) {
    return parse_acceleration(to_str(h, name));  // ValueError names the methods
  }
};
template <>
struct Codec<std::optional<RowMatrixX3d>> {
  static std::string type() { return "Optional[numpy.ndarray[float64[n, 3]]]"; }
  static py::object to_python(const std::optional<RowMatrixX3d>& v) {
    return v ? py::cast(*v) : py::object(py::none());
  }
  static std::optional<RowMatrixX3d> from_python(const py::handle& h, const char* name) {
    if (h.is_none()) return std::nullopt;
    return to_points(h, name);
  }
};

template <class Field>
using FieldType = std::decay_t<decltype(std::declval<Field>()(std::declval<SolveOptions&>()))>;

// SolveOptions from solve()'s arguments after `targets`, bound as Python binds a signature.
SolveOptions options_from(const py::args& args, const py::kwargs& kwargs) {
  SolveOptions o;
  size_t options = 0;
  visit_solve_options([&](const char*, auto, const char*) { ++options; });
  if (args.size() > options)
    throw py::type_error("solve() takes at most " + std::to_string(options + 1) + " positional arguments (" +
                         std::to_string(args.size() + 1) + " given)");
  size_t position = 0, keywords_used = 0;
  visit_solve_options([&](const char* name, auto field, const char*) {
    using T = FieldType<decltype(field)>;
    const bool by_position = position < args.size(), by_keyword = kwargs.contains(name);
    if (by_position && by_keyword)
      throw py::type_error(std::string("solve() got multiple values for argument '") + name + "'");
    if (by_position) field(o) = Codec<T>::from_python(args[position], name);
    if (by_keyword) {
      field(o) = Codec<T>::from_python(kwargs[name], name);
      ++keywords_used;
    }
    ++position;
  });
  if (keywords_used != kwargs.size()) {
    for (const auto& item : kwargs) {
      const std::string key = py::str(item.first);
      bool known = key == "targets";
      visit_solve_options([&](const char* name, auto, const char*) { known = known || key == name; });
      if (!known) throw py::type_error("solve() got an unexpected keyword argument '" + key + "'");
    }
  }
  return o;
}

// `text` wrapped at 96 columns after `indent`, its later lines indented four spaces more.
std::string wrapped(const std::string& text, const std::string& indent = "") {
  std::istringstream words(text);
  std::string out, line = indent, word;
  size_t start = line.size();  // where the current line's first word goes
  while (words >> word) {
    if (line.size() > start && line.size() + 1 + word.size() > 96) {
      out += line + "\n";
      line = indent + "    ";
      start = line.size();
    }
    line += (line.size() > start ? " " : "") + word;
  }
  return out + line + "\n";
}

// help(Deformer.solve): the signature line pybind11 would write, then each argument's text.
std::string solve_doc(const std::string& module) {
  const SolveOptions defaults;
  std::string signature = "solve(self: " + module + ".Deformer, targets: numpy.ndarray[float64[h, 3]]";
  std::string arguments = "targets: (h, 3) one target per handle, in the order given to set_constraints.\n";
  visit_solve_options([&](const char* name, auto field, const char* doc) {
    using T = FieldType<decltype(field)>;
    const std::string value = py::repr(Codec<T>::to_python(field(defaults)));
    signature += std::string(", ") + name + ": " + Codec<T>::type() + " = " + value;
    arguments += wrapped(std::string(name) + ": " + doc);
    if constexpr (std::is_same_v<T, Acceleration>) {
      for (const Method& m : kMethods)
        arguments += wrapped(std::string("\"") + acceleration_name(m.value) + "\"" +
                                 (m.value == defaults.acceleration ? " (default)" : "") + ": " + m.doc,
                             "    ");
    }
  });
  return signature + ") -> " + module + ".SolveResult\n\n" +
         "Deforms the mesh so that the handles reach their targets.\n\n" + arguments +
         "Returns a SolveResult. Ctrl-C raises KeyboardInterrupt between iterations and leaves the\n"
         "Deformer usable.\n";
}

}  // namespace

void bind_solve(py::module_& m, py::class_<Deformer>& deformer) {
  const std::string module = py::str(m.attr("__name__"));
  const SolveOptions options;
  py::dict defaults;
  visit_solve_options([&](const char* name, auto field, const char*) {
    using T = FieldType<decltype(field)>;
    defaults[name] = Codec<T>::to_python(field(options));
  });
  m.attr("SOLVE_DEFAULTS") = defaults;
  py::dict ranges;  // the integer options' ranges, for callers that check before a solve (the CLI)
  for (const IntRange& range : {kMaxIterationsRange, kAndersonWindowRange})
    ranges[range.name] = py::make_tuple(range.low, range.high);
  m.attr("SOLVE_INT_RANGES") = ranges;
  py::list methods;
  for (const Method& method : kMethods) methods.append(acceleration_name(method.value));
  m.attr("ACCELERATIONS") = py::tuple(methods);

  const std::string doc = solve_doc(module);
  py::options signatures;
  signatures.disable_function_signatures();  // solve_doc writes it, from the table
  deformer.def(
      "solve",
      [](Deformer& d, const TargetsArg& targets_arg, const py::args& args, const py::kwargs& kwargs) {
        SolveOptions o = options_from(args, kwargs);
        RowMatrixX3d t = to_points(targets_arg.obj, "targets");
        SignalCheck signals;
        o.interrupt_requested = signals.callback();
        try {
          return without_gil([&] { return d.solve(t, o); });
        } catch (const SolveInterrupted&) {  // the GIL is back: raise KeyboardInterrupt
          signals.raise_pending();
        }
      },
      py::arg("targets"), doc.c_str());
}

}  // namespace edgedeform::bindings
