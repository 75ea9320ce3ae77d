// Deformer and SolveResult. Inputs are converted while holding the GIL; the heavy work
// (graph building, assembly, factorization, iterations) runs without it.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "deformer/deformer.h"
#include "gil.h"
#include "numpy_convert.h"
#include "scalar_convert.h"
#include "typed_args.h"

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

void bind_solve(py::module_& m, py::class_<Deformer>& deformer);

void bind_deformer(py::module_& m) {
  py::class_<SolveResult>(m, "SolveResult", "Result of Deformer.solve.")
      .def_readonly("positions", &SolveResult::positions, "(n, 3) float64: every vertex, constrained ones included")
      .def_readonly("iterations", &SolveResult::iterations, "global steps taken in this call")
      .def_property_readonly(
          "energies", [](const SolveResult& r) { return py::array_t<double>(r.energies.size(), r.energies.data()); },
          "(iterations,) float64: the energy after each iteration")
      .def_property_readonly(
          "residuals", [](const SolveResult& r) { return py::array_t<double>(r.residuals.size(), r.residuals.data()); },
          "(iterations,) per iteration: largest vertex move of the plain step / rest bounding-box diagonal")
      .def_readonly("initial_energy", &SolveResult::initial_energy, "energy of `initial` when it was given, else None")
      .def_readonly("converged", &SolveResult::converged,
                    "the estimated largest vertex distance to the fixed point is below tolerance * diagonal")
      .def_readonly("distance_estimate", &SolveResult::distance_estimate,
                    "estimated largest vertex distance of positions to the fixed point / diagonal (inf: unknown)")
      .def_readonly("method", &SolveResult::method,
                    "the strategy that ran: \"lbfgs\", \"anderson\" or \"none\" (\"auto\" resolved)")
      .def_readonly("accelerated_steps", &SolveResult::accelerated_steps,
                    "Anderson steps kept, or L-BFGS steps taken")
      .def_readonly("rejected_steps", &SolveResult::rejected_steps,
                    "Anderson steps discarded by the safeguard, or L-BFGS directions that failed their line search "
                    "(the plain step was taken instead)")
      .def_readonly("line_search_fits", &SolveResult::line_search_fits,
                    "L-BFGS: local fits of its line search beyond one per iteration")
      .def_readonly("claim_checks", &SolveResult::claim_checks, "Arnoldi checks of a convergence claim (verify_claims)")
      .def_readonly("refused_claims", &SolveResult::refused_claims, "... after which the claim was refused")
      .def_readonly("warnings", &SolveResult::warnings,
                    "list[str]: not converged, vertices kept at rest, torn seams, ...")
      .def_readonly("factor_ms", &SolveResult::factor_ms, "assembly + factorization in this call (0 when reused)")
      .def_readonly("local_ms", &SolveResult::local_ms, "total ms in the local steps (rotation and scale fits)")
      .def_readonly("rhs_ms", &SolveResult::rhs_ms, "total ms building right-hand sides")
      .def_readonly("solve_ms", &SolveResult::solve_ms, "total ms in back-substitutions")
      .def_readonly("free_vertices", &SolveResult::free_vertices, "unknown vertices after constraints and region")
      .def_readonly("active_nodes", &SolveResult::active_nodes, "graph nodes whose terms touch a free vertex")
      .def("__repr__", [](const SolveResult& r) {
        return "<SolveResult iterations=" + std::to_string(r.iterations) +
               " converged=" + (r.converged ? "True" : "False") +
               " residual=" + (r.residuals.empty() ? "-" : std::to_string(r.residuals.back())) +
               " energy=" + (r.energies.empty() ? "-" : std::to_string(r.energies.back())) + ">";
      });

  py::class_<Deformer> deformer(m, "Deformer",
                                "Shape-preserving deformation of one triangle mesh: set constraints and stiffness, "
                                "then solve.");
  bind_solve(m, deformer);  // bind_solve.cpp: solve() and its options, from one table
  deformer
      .def(py::init([](const PointsArg& V, const FacesArg& F, const StrArg& domain, const BoolArg& clamp_arg) {
             RowMatrixX3d v = to_points(V.obj, "V");
             RowMatrixX3i f = to_faces(F.obj, "F");
             const Domain d = parse_domain(to_str(domain.obj, "domain"));
             const bool clamp = to_bool(clamp_arg.obj, "clamp_negative_weights");
             return without_gil([&] { return std::make_unique<Deformer>(v, f, d, clamp); });
           }),
           py::arg("V"), py::arg("F"), py::arg("domain") = "edge", py::arg("clamp_negative_weights") = true,
           R"doc(Builds the graph of a mesh.

V: (n, 3) rest positions; F: (m, 3) triangles (vertex indices).
domain: "edge" (nodes at edge midpoints, the paper's method) or "primal" (nodes at vertices).
clamp_negative_weights: clamp negative cotangent weights to 0 (keeps every term positive
semi-definite, as CGAL's ARAP does). Raises ValueError for a malformed or degenerate mesh.)doc")
      .def(
          "set_constraints",
          [](Deformer& d, const IndicesArg& handles, const OptionalIndicesArg& statics, const OptionalIndicesArg& roi,
             const OptionalFloatArg& roi_radius, const BoolArg& roi_connected, const OptionalIndicesArg& roi_from) {
            ConstraintSets sets = constraint_sets(handles.obj, statics.obj, roi.obj);
            sets.roi_radius = to_optional_float(roi_radius.obj, "roi_radius");
            sets.roi_connected = to_bool(roi_connected.obj, "roi_connected");
            if (!roi_from.obj.is_none()) sets.roi_from = to_indices(roi_from.obj, "roi_from");
            without_gil([&] { d.set_constraints(sets); });
          },
          py::arg("handles"), py::arg("static") = py::none(), py::arg("roi") = py::none(),
          py::arg("roi_radius") = py::none(), py::arg("roi_connected") = false, py::arg("roi_from") = py::none(),
          R"doc(Which vertices are moved, which stay, and which may change.

handles: (h,) vertex indices that solve() puts exactly on its targets.
static: (s,) vertex indices kept at rest, or None.
roi: (r,) the region of interest, or None for the whole mesh; vertices outside stay at rest.
roi_radius: instead of roi, the region within this distance (mesh units, rest positions) of
any handle vertex, as Blender's proportional editing: straight-line distance, or over the
surface when roi_connected (Blender's "Connected Only": along the edges and across the faces;
other components stay out).
A vertex exactly roi_radius away is inside. The same region passed as roi gives the same
positions, bit for bit.
roi_from: (k,) the vertices roi_radius is measured from, or None for the handles (Blender
measures from what it moves: a tool that pins other handles passes only the dragged ones).
Raises ValueError when a vertex is both handle and static, for a roi_radius that is not finite
and > 0, roi together with roi_radius, roi_connected or roi_from without roi_radius, or an
empty roi_from; NoFreeVertexError (a ValueError) for a roi_radius that leaves no vertex free;
IndexError when an index is out of range.)doc")
      .def(
          "set_stiffness",
          [](Deformer& d, const StiffnessArg& stiffness) {
            const py::handle& lam = stiffness.obj;
            if (py::isinstance<py::float_>(lam) || py::isinstance<py::int_>(lam)) {
              const double value = lam.cast<double>();
              // Without the GIL, like every call that waits for the Deformer's lock: a solve
              // in the main thread takes the GIL briefly to check for Ctrl-C.
              without_gil([&] { d.set_stiffness(value); });
              return;
            }
            Eigen::VectorXd v = to_vector(lam, "stiffness");
            without_gil([&] { d.set_stiffness(v); });
          },
          py::arg("stiffness"),
          R"doc(Material stiffness lambda in [0, 1]: one float for the whole mesh, or (n,) one per vertex.

1 is rigid (the 1-form energy only), 0 is smooth (the Laplacian energy only). Edge nodes take
the mean of their two vertices. Only a numeric refactorization follows; the analysis is kept.)doc")
      .def(
          "energy",
          [](const Deformer& d, const PointsArg& X) {
            RowMatrixX3d x = to_points(X.obj, "X");
            return without_gil([&] { return d.energy(x); });
          },
          py::arg("X"), "Energy of positions X (n, 3) over every node, with rotations and scales fitted to X.")
      .def_property_readonly("n_vertices", &Deformer::n_vertices, "vertices of the mesh")
      .def_property_readonly("n_faces", &Deformer::n_faces, "triangles of the mesh")
      .def_property_readonly(
          "n_nodes", &Deformer::n_nodes, "graph nodes (edges or vertices)")
      .def_property_readonly(
          "domain", [](const Deformer& d) { return std::string(domain_name(d.domain())); }, "\"edge\" or \"primal\"")
      .def_property_readonly("analyses", &Deformer::analyses, "symbolic analyses so far (reuse check)")
      .def_property_readonly("_whole_graph_built", &Deformer::whole_graph_built,
                             "whether the whole mesh's graph was built (a region's solve builds only its own)")
      .def_property_readonly("factor_nonzeros", &Deformer::factor_nonzeros,
                             "entries of the Cholesky factor from the last analysis (0 before the first solve)")
      .def(
          "edges", [](const Deformer& d) { return int_matrix(d.topology().edges); },
          "(n_edges, 2) int64 unique undirected edges, a < b (the edge domain's node order). Like arcs(), weights(), "
          "node_vertices(), node_stiffness() and energy(), it builds the whole mesh's graph on first use and keeps it "
          "(a region's solve builds only the region's)")
      .def("node_vertices",
           [](const Deformer& d) {
             const RowMatrixX2i& nv = d.graph().node_vertices;
             if (d.domain() == Domain::Edge) return int_matrix(nv);
             py::array_t<int64_t> out({nv.rows(), static_cast<Eigen::Index>(1)});
             auto o = out.mutable_unchecked<2>();
             for (Eigen::Index r = 0; r < nv.rows(); ++r) o(r, 0) = nv(r, 0);
             return out;
           },
           "the vertices of each node: (n_edges, 2) in the edge domain, (n, 1) in the primal one")
      .def(
          "arcs", [](const Deformer& d) { return int_matrix(d.graph().arcs); },
          "(n_arcs, 2) int64 node pairs i < j of the graph")
      .def(
          "weights", [](const Deformer& d) { return Eigen::VectorXd(d.graph().arc_weights); },
          "(n_arcs,) float64 arc weights (after clamping, when on)")
      .def(
          "node_stiffness",
          [](const Deformer& d) {
            // node_lambda() waits for a solve in another thread
            return without_gil([&] { return d.node_lambda(); });
          },
          "(n_nodes,) float64 lambda per node under the current stiffness")
      .def("_laplacian_coo", [](const Deformer& d) { return to_coo(d.graph().laplacian()); })
      .def("_node_matrix_coo", [](const Deformer& d) { return to_coo(d.graph().node_matrix()); })
      // Inspection of the one-step map and its derivative (tests and bench/): vectors over the free vertices.
      .def_property_readonly("free_vertices", [](const Deformer& d) { return d.free_vertices(); },
                             "list[int]: the free vertices of the current constraints, in the order of the "
                             "free-vertex vectors of _one_step and _jacobian")
      .def("_one_step", [](Deformer& d, const py::handle& X) { return d.one_step_map(to_points(X, "X")); },
           "G(X) over the free vertices (#free, 3)")
      .def("_jacobian",
           [](Deformer& d, const py::handle& X, const Eigen::MatrixXd& dX, bool k_product) {
             return d.jacobian_product(to_points(X, "X"), dX, k_product);
           },
           py::arg("X"), py::arg("dX"), py::arg("k_product") = false,
           "J_G dX at X (analytic), or K dX = A (I - J_G) dX with k_product")
      .def("_local_fit",
           [](Deformer& d, const py::handle& X) {
             const LocalFit fit = d.local_fit_at(to_points(X, "X"));
             py::array_t<double> R({static_cast<py::ssize_t>(fit.rotation.size()), py::ssize_t{3}, py::ssize_t{3}});
             auto r = R.mutable_unchecked<3>();
             for (size_t t = 0; t < fit.rotation.size(); ++t)
               for (int i = 0; i < 3; ++i)
                 for (int j = 0; j < 3; ++j) r(static_cast<py::ssize_t>(t), i, j) = fit.rotation[t](i, j);
             return py::make_tuple(R, Eigen::VectorXd(fit.scale));
           },
           "(rotations (#terms, 3, 3), scales (#terms,)) of the local fit at X")
      .def("_global_step",
           [](Deformer& d, const py::handle& X, const py::array_t<double, py::array::c_style | py::array::forcecast>& R,
              const Eigen::VectorXd& scale) {
             if (R.ndim() != 3 || R.shape(1) != 3 || R.shape(2) != 3)
               throw std::invalid_argument("rotations must be a (#terms, 3, 3) array");
             std::vector<Eigen::Matrix3d> rotation(static_cast<size_t>(R.shape(0)));
             auto r = R.unchecked<3>();
             for (size_t t = 0; t < rotation.size(); ++t)
               for (int i = 0; i < 3; ++i)
                 for (int j = 0; j < 3; ++j) rotation[t](i, j) = r(static_cast<py::ssize_t>(t), i, j);
             return d.global_step_with(to_points(X, "X"), rotation, scale);
           },
           py::arg("X"), py::arg("rotations"), py::arg("scales"),
           "the global step's free positions (#free, 3) for these rotations and scales, X's fixed rows");
}

}  // namespace edgedeform::bindings
