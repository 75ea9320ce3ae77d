#include <pybind11/stl.h>

#include "local_fit/metrics.h"
#include "gil.h"
#include "numpy_convert.h"
#include "typed_args.h"

namespace edgedeform::bindings {

void bind_metrics(py::module_& m) {
  m.def(
      "metrics",
      [](const PointsArg& rest, const FacesArg& F, const PointsArg& deformed, const OptionalIndicesArg& handles,
         const OptionalTargetsArg& targets) {
        const RowMatrixX3d r = to_points(rest.obj, "V_rest");
        const RowMatrixX3i f = to_faces(F.obj, "F");
        const RowMatrixX3d x = to_points(deformed.obj, "V_def");
        const std::vector<int> h = to_indices(handles.obj, "handles");
        const RowMatrixX3d t = targets.obj.is_none() ? RowMatrixX3d(0, 3) : to_points(targets.obj, "targets");
        const QualityMetrics q = without_gil([&] { return compute_metrics(r, f, x, h, t); });
        py::dict out;
        out["handle_error"] = q.handle_error;
        out["mean_edge_strain"] = q.mean_edge_strain;
        out["max_edge_strain"] = q.max_edge_strain;
        out["mean_dihedral_change"] = q.mean_dihedral_change;
        out["arap_energy"] = q.arap_energy;
        out["arap_energy_normalized"] = q.arap_energy_normalized;
        return out;
      },
      py::arg("V_rest"), py::arg("F"), py::arg("V_def"), py::arg("handles") = py::none(), py::arg("targets") = py::none(),
      R"doc(Quality of a deformed mesh against its rest shape.

V_rest, V_def: (n, 3) rest and deformed positions; F: (m, 3) triangles;
handles: (h,) handle vertex indices and targets: (h, 3) their targets, or None.
Returns a dict: handle_error (max distance of a handle to its target),
mean_edge_strain and max_edge_strain (|l - l0| / l0 over mesh edges),
mean_dihedral_change (|theta - theta0| in radians, the mean over the face pairs at each
edge: one pair inside a manifold surface, three at a fin's edge), arap_energy (classic primal ARAP energy,
clamped cotangent spokes) and arap_energy_normalized (arap_energy divided by
sum_ij w_ij |e0_ij|^2, so meshes of any size and scale compare).)doc");
}

}  // namespace edgedeform::bindings
