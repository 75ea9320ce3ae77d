// The compiled part of the edgedeform package: edgedeform._core.
#include <pybind11/pybind11.h>

#include "linear_algebra/build_info.h"
#include "base/serial_blas.h"
#include "base/errors.h"

namespace py = pybind11;

namespace edgedeform::bindings {
void bind_deformer(py::module_& m);
void bind_metrics(py::module_& m);
}  // namespace edgedeform::bindings

PYBIND11_MODULE(_core, m) {
  m.doc() = "edgedeform native core: edge-graph deformation solver";
  py::register_exception<edgedeform::FactorizationError>(m, "FactorizationError", PyExc_RuntimeError);
  // Errors a caller may want to tell apart, by type (never by message text).
  py::register_exception<edgedeform::NoFreeVertexError>(m, "NoFreeVertexError", PyExc_ValueError);
  m.def("build_info", [] {
    py::dict info;
    info["version"] = edgedeform::version();
    info["solver"] = edgedeform::solver_backend();
    info["openmp"] = edgedeform::has_openmp();
    info["threads"] = edgedeform::max_threads();
    info["eigen"] = edgedeform::eigen_version();
    info["compiler"] = edgedeform::compiler();
    // Whether factorizations run their BLAS on one thread (serial_blas.h): the condition for
    // the same positions on any number of threads.
    info["serial_blas_factor"] = edgedeform::SerialBlas::available();
    return info;
  }, "How this module was built: version, sparse solver, OpenMP and its threads, Eigen, compiler, "
     "and whether factorizations run their BLAS on one thread (serial_blas_factor).");
  edgedeform::bindings::bind_deformer(m);
  edgedeform::bindings::bind_metrics(m);
}
