#include "system/warm_state.h"

#include <utility>

namespace edgedeform {

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
  if (warm && !node_fit_.empty())  // constraints changed since
    for (size_t t = 0; t < T; ++t) {
      const auto kept = node_fit_.find(sys.term_nodes[t]);
      if (kept == node_fit_.end()) continue;  // never solved: R = I, s = 1
      fit.rotation[t] = kept->second.rotation;
      fit.right_vectors[t] = kept->second.right_vectors;
      fit.scale(static_cast<Eigen::Index>(t)) = kept->second.scale;
    }
  return fit;
}

void WarmState::store(LocalFit fit) {
  last_fit_ = std::move(fit);
  last_fit_valid_ = true;
}

void WarmState::keep_per_node(const std::vector<int>& nodes) {
  if (!last_fit_valid_) return;
  node_fit_.reserve(node_fit_.size() + nodes.size());
  for (size_t t = 0; t < nodes.size(); ++t)
    node_fit_[nodes[t]] = {last_fit_.rotation[t], last_fit_.right_vectors[t],
                           last_fit_.scale(static_cast<Eigen::Index>(t))};
  last_fit_valid_ = false;
}

}  // namespace edgedeform
