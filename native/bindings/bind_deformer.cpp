// Deformer and SolveResult. Inputs are converted while holding the GIL; the heavy work
// (graph building, assembly, factorization, iterations) runs without it.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "edgedeform/deformer.h"
#include "edgedeform/errors.h"
#include "numpy_convert.h"
#include "signal_check.h"

namespace edgedeform::bindings {

namespace {

ConstraintSets constraint_sets(const py::handle& handles, const py::handle& statics, const py::handle& roi) {
  ConstraintSets sets;
  sets.handles = to_indices(handles, "handles");
  sets.statics = to_indices(statics, "static");
  if (!roi.is_none()) sets.roi = to_indices(roi, "roi");
  return sets;
}

py::array_t<int64_t> int_matrix(const RowMatrixX2i& M) {
  py::array_t<int64_t> out({M.rows(), static_cast<Eigen::Index>(2)});
  auto o = out.mutable_unchecked<2>();
  for (Eigen::Index r = 0; r < M.rows(); ++r)
    for (int c = 0; c < 2; ++c) o(r, c) = M(r, c);
  return out;
}

}  // namespace

void bind_deformer(py::module_& m) {
  py::class_<SolveResult>(m, "SolveResult", "Result of Deformer.solve.")
      .def_readonly("positions", &SolveResult::positions, "(n,3) float64, every vertex")
      .def_readonly("iterations", &SolveResult::iterations)
      .def_property_readonly("energies",
                             [](const SolveResult& r) { return py::array_t<double>(r.energies.size(), r.energies.data()); })
      .def_property_readonly(
          "residuals", [](const SolveResult& r) { return py::array_t<double>(r.residuals.size(), r.residuals.data()); },
          "(iterations,) per iteration: largest vertex move of the plain step / rest bounding-box diagonal")
      .def_readonly("initial_energy", &SolveResult::initial_energy)
      .def_readonly("converged", &SolveResult::converged,
                    "the estimated largest vertex distance to the fixed point is below tolerance * diagonal")
      .def_readonly("distance_estimate", &SolveResult::distance_estimate,
                    "estimated largest vertex distance of positions to the fixed point / diagonal (inf: unknown)")
      .def_readonly("accelerated_steps", &SolveResult::accelerated_steps, "Anderson steps taken")
      .def_readonly("rejected_steps", &SolveResult::rejected_steps, "Anderson steps the safeguard discarded")
      .def_readonly("warnings", &SolveResult::warnings)
      .def_readonly("factor_ms", &SolveResult::factor_ms)
      .def_readonly("local_ms", &SolveResult::local_ms)
      .def_readonly("rhs_ms", &SolveResult::rhs_ms)
      .def_readonly("solve_ms", &SolveResult::solve_ms)
      .def_readonly("free_vertices", &SolveResult::free_vertices)
      .def_readonly("active_nodes", &SolveResult::active_nodes)
      .def("__repr__", [](const SolveResult& r) {
        return "<SolveResult iterations=" + std::to_string(r.iterations) +
               " converged=" + (r.converged ? "True" : "False") +
               " residual=" + (r.residuals.empty() ? "-" : std::to_string(r.residuals.back())) +
               " energy=" + (r.energies.empty() ? "-" : std::to_string(r.energies.back())) + ">";
      });

  py::class_<Deformer>(m, "Deformer")
      .def(py::init([](const py::handle& V, const py::handle& F, const std::string& domain, bool clamp) {
             RowMatrixX3d v = to_points(V, "V");
             RowMatrixX3i f = to_faces(F, "F");
             const Domain d = parse_domain(domain);
             py::gil_scoped_release release;
             return std::make_unique<Deformer>(v, f, d, clamp);
           }),
           py::arg("V"), py::arg("F"), py::arg("domain") = "edge", py::arg("clamp_negative_weights") = true)
      .def(
          "set_constraints",
          [](Deformer& d, const py::handle& handles, const py::handle& statics, const py::handle& roi) {
            ConstraintSets sets = constraint_sets(handles, statics, roi);
            py::gil_scoped_release release;
            d.set_constraints(sets);
          },
          py::arg("handles"), py::arg("static") = py::none(), py::arg("roi") = py::none(),
          "Handle, static and region-of-interest vertex indices (roi None = every vertex).")
      .def(
          "set_stiffness",
          [](Deformer& d, const py::handle& lam) {
            if (py::isinstance<py::float_>(lam) || py::isinstance<py::int_>(lam)) {
              const double value = lam.cast<double>();
              // Without the GIL, like every call that waits for the Deformer's lock: a solve
              // in another thread takes the GIL briefly to check for Ctrl-C.
              py::gil_scoped_release release;
              d.set_stiffness(value);
              return;
            }
            Eigen::VectorXd v = to_vector(lam, "stiffness");
            py::gil_scoped_release release;
            d.set_stiffness(v);
          },
          py::arg("stiffness"), "lambda in [0,1]: one float, or one value per vertex.")
      .def(
          "solve",
          [](Deformer& d, const py::handle& targets, int max_iterations, double tolerance, bool warm_start,
             const py::handle& initial, const std::string& acceleration, int anderson_window) {
            SolveOptions o;
            o.max_iterations = max_iterations;
            o.tolerance = tolerance;
            o.warm_start = warm_start;
            o.acceleration = parse_acceleration(acceleration);
            o.anderson_window = anderson_window;
            if (!initial.is_none()) o.initial = to_points(initial, "initial");
            RowMatrixX3d t = to_points(targets, "targets");
            SignalCheck signals;
            o.interrupt_requested = signals.callback();
            try {
              py::gil_scoped_release release;
              return d.solve(t, o);
            } catch (const SolveInterrupted&) {  // the GIL is back: raise KeyboardInterrupt
              signals.raise_pending();
            }
          },
          py::arg("targets"), py::arg("max_iterations") = SolveOptions{}.max_iterations,
          py::arg("tolerance") = SolveOptions{}.tolerance, py::arg("warm_start") = true, py::arg("initial") = py::none(),
          py::arg("acceleration") = "anderson", py::arg("anderson_window") = SolveOptions{}.anderson_window,
          "Local/global iterations until the estimated largest vertex distance to the fixed point is below\n"
          "tolerance * rest bounding-box diagonal, or max_iterations. acceleration: \"anderson\" | \"none\".\n"
          "A warm solve with unchanged targets continues the previous iteration (its Anderson history too).")
      .def(
          "energy",
          [](const Deformer& d, const py::handle& X) {
            RowMatrixX3d x = to_points(X, "X");
            py::gil_scoped_release release;
            return d.energy(x);
          },
          py::arg("X"), "Energy of positions X, rotations and scales fitted to X, over every node.")
      .def_property_readonly("n_vertices", &Deformer::n_vertices)
      .def_property_readonly("n_faces", &Deformer::n_faces)
      .def_property_readonly("n_nodes", [](const Deformer& d) { return d.graph().n_nodes; })
      .def_property_readonly("domain", [](const Deformer& d) { return std::string(domain_name(d.domain())); })
      .def_property_readonly("analyses", &Deformer::analyses, "symbolic analyses so far (reuse check)")
      .def_property_readonly("factor_nonzeros", &Deformer::factor_nonzeros,
                             "entries of the Cholesky factor from the last analysis (0 before the first solve)")
      .def("edges", [](const Deformer& d) { return int_matrix(d.topology().edges); })
      .def("node_vertices",
           [](const Deformer& d) {
             const RowMatrixX2i& nv = d.graph().node_vertices;
             if (d.domain() == Domain::Edge) return int_matrix(nv);
             py::array_t<int64_t> out({nv.rows(), static_cast<Eigen::Index>(1)});
             auto o = out.mutable_unchecked<2>();
             for (Eigen::Index r = 0; r < nv.rows(); ++r) o(r, 0) = nv(r, 0);
             return out;
           })
      .def("arcs", [](const Deformer& d) { return int_matrix(d.graph().arcs); })
      .def("weights", [](const Deformer& d) { return Eigen::VectorXd(d.graph().arc_weights); })
      .def("node_stiffness", [](const Deformer& d) { return Eigen::VectorXd(d.node_lambda()); })
      .def("_laplacian_coo", [](const Deformer& d) { return to_coo(d.graph().laplacian()); })
      .def("_node_matrix_coo", [](const Deformer& d) { return to_coo(d.graph().node_matrix()); });
}

}  // namespace edgedeform::bindings
