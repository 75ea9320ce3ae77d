#include <pybind11/stl.h>

#include "edgedeform/metrics.h"
#include "numpy_convert.h"

namespace edgedeform::bindings {

void bind_metrics(py::module_& m) {
  m.def(
      "metrics",
      [](const py::handle& rest, const py::handle& F, const py::handle& deformed, const py::handle& handles,
         const py::handle& targets) {
        const RowMatrixX3d r = to_points(rest, "V_rest");
        const RowMatrixX3i f = to_faces(F, "F");
        const RowMatrixX3d x = to_points(deformed, "V_def");
        const std::vector<int> h = to_indices(handles, "handles");
        const RowMatrixX3d t = targets.is_none() ? RowMatrixX3d(0, 3) : to_points(targets, "targets");
        QualityMetrics q;
        {
          py::gil_scoped_release release;
          q = compute_metrics(r, f, x, h, t);
        }
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
      "Quality of a deformed mesh against its rest shape (see docs/api.md).");
}

}  // namespace edgedeform::bindings
