#include "strategies/iteration_state.h"

namespace edgedeform {

namespace {
void gather_rows(const RowMatrixX3d& from, const std::vector<int>& rows, Eigen::MatrixXd& to) {
  to.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (size_t k = 0; k < rows.size(); ++k) to.row(static_cast<Eigen::Index>(k)) = from.row(rows[k]);
}
}  // namespace

void IterationState::restart(const RowMatrixX3d& targets, const RowMatrixX3d& rest,
                             const std::vector<int>& free_vertices, bool keep_positions, int anderson_window) {
  const int nf = static_cast<int>(free_vertices.size());
  if (point.y.rows() != nf || !positions_valid_ || !keep_positions)  // measure the first step from rest
    gather_rows(rest, free_vertices, point.y);
  plain.restart(nf, anderson_window);
  quasi_newton.restart(nf);
  last_method = Acceleration::Automatic;
  targets_ = targets;
  point.fitted = false;  // the fit is not fit(y) yet
}

void IterationState::start_at(const RowMatrixX3d& initial, const std::vector<int>& free_vertices) {
  gather_rows(initial, free_vertices, point.y);
}

}  // namespace edgedeform
