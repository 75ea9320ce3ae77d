// A term's three energy shares, written out once (docs/design.md §3 with the primal similarity
// floor, stiffness.h): the rigid 1-form term weighs lambda_t, the as-similar-as-possible
// 1-form term phi_t, and the rotation- and scale-aware Laplacian term what is left,
// 1 - lambda_t - phi_t. Assembly (constrained_system.cpp), the right side
// (rotation_operator), the energy (local_step.cpp) and its derivative all take it from here.
#pragma once

namespace edgedeform {

struct TermShares {
  double rigid = 1.0;    // lambda_t
  double similar = 0.0;  // phi_t
  double smooth = 0.0;   // 1 - lambda_t - phi_t
  double one_form() const { return rigid + similar; }  // what the 1-form arcs weigh in A
};

inline TermShares term_shares(double lambda, double similar) { return {lambda, similar, 1.0 - lambda - similar}; }

}  // namespace edgedeform
