// One fixed solve, the same on every platform: read a mesh with its edit, run plain
// local/global iterations, write the positions. The `windows` tests run it natively (the
// Linux reference) and under wine (the Windows build) and compare (compare_positions.py).
//
//   solve_lift INPUT OUTPUT ITERATIONS
// INPUT (text, written by make_lift_input.py): "nv nf nh ns lambda", then nv rows x y z, nf
// rows a b c, nh handle ids, ns static ids, nh target rows. OUTPUT: "nv iterations energy",
// then nv rows x y z, every double printed exactly (%.17g).
#include <algorithm>
#include <cstdio>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>

#include "linear_algebra/build_info.h"
#include "deformer/deformer.h"

namespace {

template <typename T>
T next(std::istream& in, const char* what) {
  T value;
  if (!(in >> value)) throw std::runtime_error(std::string("input ends before ") + what);
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: solve_lift INPUT OUTPUT ITERATIONS\n");
    return 2;
  }
  try {
    std::ifstream in(argv[1]);
    if (!in) throw std::runtime_error(std::string("cannot read ") + argv[1]);
    const int nv = next<int>(in, "the counts"), nf = next<int>(in, "the counts");
    const int nh = next<int>(in, "the counts"), ns = next<int>(in, "the counts");
    const double lambda = next<double>(in, "lambda");
    edgedeform::RowMatrixX3d V(nv, 3), targets(nh, 3);
    edgedeform::RowMatrixX3i F(nf, 3);
    for (int i = 0; i < nv; ++i)
      for (int c = 0; c < 3; ++c) V(i, c) = next<double>(in, "the vertices");
    for (int i = 0; i < nf; ++i)
      for (int c = 0; c < 3; ++c) F(i, c) = next<int>(in, "the faces");
    edgedeform::ConstraintSets sets;
    for (int i = 0; i < nh; ++i) sets.handles.push_back(next<int>(in, "the handles"));
    for (int i = 0; i < ns; ++i) sets.statics.push_back(next<int>(in, "the static vertices"));
    for (int i = 0; i < nh; ++i)
      for (int c = 0; c < 3; ++c) targets(i, c) = next<double>(in, "the targets");

    edgedeform::Deformer deformer(V, F, edgedeform::Domain::Edge);
    deformer.set_constraints(sets);
    deformer.set_stiffness(lambda);
    edgedeform::SolveOptions options;
    options.max_iterations = std::stoi(argv[3]);
    options.tolerance = 0.0;  // exactly ITERATIONS iterations
    options.acceleration = edgedeform::Acceleration::None;
    options.warm_start = false;
    const edgedeform::SolveResult result = deformer.solve(targets, options);

    std::FILE* out = std::fopen(argv[2], "w");
    if (out == nullptr) throw std::runtime_error(std::string("cannot write ") + argv[2]);
    std::fprintf(out, "%d %d %.17g\n", nv, result.iterations,
                 result.energies.empty() ? 0.0 : result.energies.back());
    for (int i = 0; i < nv; ++i)
      std::fprintf(out, "%.17g %.17g %.17g\n", result.positions(i, 0), result.positions(i, 1), result.positions(i, 2));
    std::fclose(out);
    std::printf("solve_lift: %s, %d vertices, %d iterations, energy %.17g, factor %.0f ms, %.0f ms "
                "per iteration\n", edgedeform::solver_backend(), nv, result.iterations,
                result.energies.empty() ? 0.0 : result.energies.back(), result.factor_ms,
                (result.local_ms + result.rhs_ms + result.solve_ms) / std::max(1, result.iterations));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "solve_lift: %s\n", e.what());
    return 1;
  }
}
