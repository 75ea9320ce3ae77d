#include "edgedeform/warm_state.h"

#include <utility>

namespace edgedeform {

WarmState::WarmState(int n_nodes)
    : node_rotation_(static_cast<size_t>(n_nodes), Eigen::Matrix3d::Identity()),
      node_scale_(Eigen::VectorXd::Ones(n_nodes)),
      node_right_vectors_(node_rotation_) {}

LocalFit WarmState::starting_fit(const ConstrainedSystem& sys, bool warm) {
  const auto T = static_cast<size_t>(sys.n_terms());
  LocalFit fit;
  if (warm && last_fit_valid_) {  // live editing: no copies
    last_fit_valid_ = false;
    return std::move(last_fit_);
  }
  // A cold start (or an initial shape) begins every SVD at V = I, so that it does not depend
  // on what this Deformer solved before.
  fit.rotation.assign(T, Eigen::Matrix3d::Identity());
  fit.right_vectors.assign(T, Eigen::Matrix3d::Identity());
  fit.scale = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(T));
  if (warm && has_previous_)  // constraints changed since
    for (size_t t = 0; t < T; ++t) {
      const auto i = static_cast<size_t>(sys.term_nodes[t]);
      fit.rotation[t] = node_rotation_[i];
      fit.right_vectors[t] = node_right_vectors_[i];
      fit.scale(static_cast<Eigen::Index>(t)) = node_scale_(sys.term_nodes[t]);
    }
  return fit;
}

void WarmState::store(LocalFit fit) {
  last_fit_ = std::move(fit);
  last_fit_valid_ = true;
}

void WarmState::keep_per_node(const std::vector<int>& nodes) {
  if (!last_fit_valid_) return;
  for (size_t t = 0; t < nodes.size(); ++t) {
    const auto i = static_cast<size_t>(nodes[t]);
    node_rotation_[i] = last_fit_.rotation[t];
    node_right_vectors_[i] = last_fit_.right_vectors[t];
    node_scale_(nodes[t]) = last_fit_.scale(static_cast<Eigen::Index>(t));
  }
  has_previous_ = true;
  last_fit_valid_ = false;
}

}  // namespace edgedeform
