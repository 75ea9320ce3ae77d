// A handle-set change without a new assembly. When a constraint set frees only vertices
// that another set `whole` freed (a handle group added, a vertex pinned, the group released
// again), its operators are sub-matrices of the whole set's:
//   A    = A_whole[F, F],
//   K    = [A_whole | K_whole][F, C]   (C: the fixed vertices the part's terms touch),
//   H    = H_whole's rows F, its terms renumbered,
// because an arc or Laplacian row that touches a vertex of F belongs to a term active in
// both sets (a term is active when its node or a neighbour holds a free vertex), so the
// entries in rows F sum the same terms with the same weights; the terms active only in the
// whole set touch no vertex of F. Slicing costs a pass over the kept entries, against the
// sparse products of a fresh assembly.
#pragma once

#include "system/constrained_system.h"

namespace edgedeform {

// Whether every free vertex of `part` is free in `whole` (the same mesh).
bool frees_subset(const ConstrainedSystem& part, const ConstrainedSystem& whole);

// Whether restrict_assembly gives `part` the sparsity of its own assembly at vertex_lambda:
// frees_subset, and the Laplacian term present in both or in neither (with lambda = 1 on
// all of part's terms but not on whole's, A_whole[F, F] would carry the Laplacian's
// pattern as explicit zeros, and its factor the fill of a pattern part does not have).
bool restriction_keeps_pattern(const ConstrainedSystem& whole, const ConstrainedSystem& part,
                               const Eigen::VectorXd& vertex_lambda);

// The operators of `part` (a layout: no J1, J2 needed) at vertex_lambda (#V), taken from
// `whole_assembled`, which must be `whole`'s at the same vertex_lambda (std::logic_error
// otherwise, or when part frees a vertex whole does not). Equal to assemble_system(part)
// up to the order of floating-point sums.
AssembledSystem restrict_assembly(const AssembledSystem& whole_assembled, const ConstrainedSystem& whole,
                                  const ConstrainedSystem& part, const Eigen::VectorXd& vertex_lambda);

}  // namespace edgedeform
