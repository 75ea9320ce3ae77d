// Deformer.solve and the module's SOLVE_DEFAULTS, SOLVE_INT_RANGES and ACCELERATIONS.
// solve()'s keyword arguments are pybind11's own `py::arg(name) = default`, listed once in
// solve_arguments() with the defaults of SolveOptions{}; the same list makes SOLVE_DEFAULTS,
// which the command line, the add-on, the benchmarks and docs/api.md read
// (docs/decisions/0050-one-source-for-solve-options.md). A new option: a SolveOptions field,
// a parameter of solve() below, one line in solve_arguments() and one in kSolveDoc.
#include <string>
#include <tuple>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "deformer/deformer.h"
#include "base/errors.h"
#include "gil.h"
#include "numpy_convert.h"
#include "scalar_convert.h"
#include "signal_check.h"
#include "typed_args.h"

namespace edgedeform::bindings {

namespace {

// solve()'s keyword arguments after `targets`, in the order of its parameters.
auto solve_arguments() {
  const SolveOptions o;
  return std::make_tuple(py::arg("max_iterations") = o.max_iterations, py::arg("tolerance") = o.tolerance,
                         py::arg("warm_start") = o.warm_start, py::arg("initial") = py::none(),
                         py::arg("acceleration") = std::string(acceleration_name(o.acceleration)),
                         py::arg("anderson_window") = o.anderson_window, py::arg("verify_claims") = o.verify_claims);
}

// Each argument is taken as any object and converted here, so that a wrong one is an error
// that names it (scalar_convert.h, numpy_convert.h), never pybind11's listing of every argument.
SolveResult solve(Deformer& d, const TargetsArg& targets, const IntArg& max_iterations, const FloatArg& tolerance,
                  const BoolArg& warm_start, const OptionalPointsArg& initial, const StrArg& acceleration,
                  const IntArg& anderson_window, const BoolArg& verify_claims) {
  SolveOptions o;
  o.max_iterations = to_int(max_iterations.obj, kMaxIterationsRange);
  o.tolerance = to_float(tolerance.obj, "tolerance");
  o.warm_start = to_bool(warm_start.obj, "warm_start");
  if (!initial.obj.is_none()) o.initial = to_points(initial.obj, "initial");
  o.acceleration = parse_acceleration(to_str(acceleration.obj, "acceleration"));  // ValueError names the methods
  o.anderson_window = to_int(anderson_window.obj, kAndersonWindowRange);
  o.verify_claims = to_bool(verify_claims.obj, "verify_claims");
  const RowMatrixX3d t = to_points(targets.obj, "targets");
  SignalCheck signals;
  o.interrupt_requested = signals.callback();
  try {
    return without_gil([&] { return d.solve(t, o); });
  } catch (const SolveInterrupted&) {  // the GIL is back: raise KeyboardInterrupt
    signals.raise_pending();
  }
}

// The methods `acceleration` takes, in the order help() and ACCELERATIONS list them.
struct Method {
  Acceleration value;
  const char* doc;
};
const Method kMethods[] = {
    {Acceleration::Automatic, "the measured rule: \"lbfgs\" where stiffness is 1 on every vertex, else\n"
                              "        \"anderson\""},
    {Acceleration::Lbfgs, "L-BFGS on the energy, the plain step its first direction, with a line\n"
                          "        search (needs stiffness 1 on every vertex: else runs \"anderson\" and warns)"},
    {Acceleration::Anderson, "Anderson-accelerated local/global"},
    {Acceleration::None, "the plain local/global method"},
};

const char* const kSolveDoc = R"doc(Deforms the mesh so that the handles reach their targets.

targets: (h, 3) one target per handle, in the order given to set_constraints.
max_iterations: most local/global iterations in this call.
tolerance: stop when the estimated largest vertex distance to the fixed point is below
    tolerance times the rest bounding-box diagonal; then result.converged is True.
warm_start: start from the previous solve's shape; with unchanged targets this continues the
    same iteration (Anderson history or L-BFGS pairs included), so repeated short calls settle
    on the cold solve's shape.
initial: (n, 3) positions to start from instead (a local step on them first), or None.
acceleration: how the fixed point is reached; each method ends at a fixed point of the same
    map (where the energy has several near one another, methods can end at different ones):
)doc";

const char* const kSolveDocEnd = R"doc(verify_claims: before claiming convergence, estimate J_G's largest modulus by 30 Arnoldi
    steps at the point (each a back-substitution) and claim only if the distance bound with it
    holds too (a secant estimate can miss a slow mode).
Returns a SolveResult. Ctrl-C raises KeyboardInterrupt between iterations and leaves the
Deformer usable.)doc";

// kSolveDoc, the methods (the default marked), anderson_window's range, kSolveDocEnd.
std::string solve_doc() {
  std::string doc = kSolveDoc;
  for (const Method& m : kMethods)
    doc += std::string("    \"") + acceleration_name(m.value) + "\"" +
           (m.value == SolveOptions{}.acceleration ? " (default)" : "") + ": " + m.doc + "\n";
  doc += "anderson_window: how many past iterates Anderson acceleration combines (" +
         std::to_string(kAndersonWindowRange.low) + ".." + std::to_string(kAndersonWindowRange.high) + ").\n";
  return doc + kSolveDocEnd;
}

}  // namespace

void bind_solve(py::module_& m, py::class_<Deformer>& deformer) {
  const auto arguments = solve_arguments();
  py::dict defaults;
  std::apply([&](const auto&... argument) { ((defaults[argument.name] = argument.value), ...); }, arguments);
  m.attr("SOLVE_DEFAULTS") = defaults;
  py::dict ranges;  // the integer options' ranges, for callers that check before a solve (the CLI)
  for (const IntRange& range : {kMaxIterationsRange, kAndersonWindowRange})
    ranges[range.name] = py::make_tuple(range.low, range.high);
  m.attr("SOLVE_INT_RANGES") = ranges;
  py::list methods;
  for (const Method& method : kMethods) methods.append(acceleration_name(method.value));
  m.attr("ACCELERATIONS") = py::tuple(methods);

  const std::string doc = solve_doc();  // pybind11 copies it
  std::apply([&](const auto&... argument) { deformer.def("solve", &solve, py::arg("targets"), argument..., doc.c_str()); },
             arguments);
}

}  // namespace edgedeform::bindings
