// libFuzzer target for the C++ core: random and malformed meshes, constraints, stiffness,
// targets and solve options, and real meshes (tests/data) with random edits.
//
// The contract checked on every input: no crash and no sanitizer report (the build adds
// ASan + UBSan), and each call either throws one of the documented errors
// (std::invalid_argument, std::out_of_range, FactorizationError) or returns finite
// positions with every handle exactly on its target and every static vertex at rest.
// Anything else aborts, which libFuzzer reports with the input that caused it.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "deformer/deformer.h"
#include "base/errors.h"
#include "local_fit/metrics.h"
#include "../cpp/test_meshes.h"

using namespace edgedeform;

namespace {

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz_core: contract broken: %s\n", what.c_str());
  std::abort();
}

// A coordinate: mostly ordinary, sometimes extreme or non-finite (from raw bytes).
double coordinate(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange<int>(0, 7)) {
    case 0: return in.ConsumeFloatingPoint<double>();  // anything, NaN and inf included
    case 1: return 0.0;
    default: return in.ConsumeFloatingPointInRange<double>(-2.0, 2.0);
  }
}

std::vector<int> index_set(FuzzedDataProvider& in, int n, size_t max_size) {
  std::vector<int> out(in.ConsumeIntegralInRange<size_t>(0, max_size));
  for (int& v : out) v = in.ConsumeIntegralInRange<int>(-1, n);  // -1 and n are out of range
  return out;
}

test::TestMesh random_mesh(FuzzedDataProvider& in) {
  test::TestMesh m;
  const int n = in.ConsumeIntegralInRange<int>(0, 40);
  m.V.resize(n, 3);
  for (int v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c) m.V(v, c) = coordinate(in);
  const int faces = in.ConsumeIntegralInRange<int>(0, 60);
  m.F.resize(faces, 3);
  for (int f = 0; f < faces; ++f)
    for (int c = 0; c < 3; ++c) m.F(f, c) = in.ConsumeIntegralInRange<int>(-1, n);
  return m;
}

// A real mesh with a few random edits: moved or collapsed vertices, rewired or extra faces.
test::TestMesh edited_real_mesh(FuzzedDataProvider& in) {
  static const test::TestMesh plane = test::read_off("cgal_plane.off");
  static const test::TestMesh fin = test::grid_with_fin(8, 6);
  test::TestMesh m = in.ConsumeIntegralInRange<int>(0, 3) == 0 ? plane : fin;  // the plane is slow
  const int n = static_cast<int>(m.V.rows());
  const int edits = in.ConsumeIntegralInRange<int>(0, 8);
  for (int e = 0; e < edits && in.remaining_bytes() > 0; ++e) {
    const int v = in.ConsumeIntegralInRange<int>(0, n - 1);
    switch (in.ConsumeIntegralInRange<int>(0, 3)) {
      case 0: m.V.row(v) += Eigen::RowVector3d(coordinate(in), coordinate(in), coordinate(in)); break;
      case 1: m.V.row(v) = m.V.row(in.ConsumeIntegralInRange<int>(0, n - 1)); break;  // collapse
      case 2: m.F(in.ConsumeIntegralInRange<int>(0, static_cast<int>(m.F.rows()) - 1), in.ConsumeIntegralInRange<int>(0, 2)) = v; break;
      default: {  // an extra face on an existing edge: non-manifold
        const Eigen::Index f = in.ConsumeIntegralInRange<int>(0, static_cast<int>(m.F.rows()) - 1);
        m.F.conservativeResize(m.F.rows() + 1, 3);
        m.F.row(m.F.rows() - 1) << m.F(f, 0), m.F(f, 1), v;
      }
    }
  }
  return m;
}

void check_result(const SolveResult& r, const RowMatrixX3d& rest, const ConstraintSets& sets,
                  const RowMatrixX3d& targets) {
  if (r.positions.rows() != rest.rows()) fail("positions have the wrong row count");
  if (!r.positions.allFinite()) fail("non-finite positions");
  for (size_t h = 0; h < sets.handles.size(); ++h)
    if (r.positions.row(sets.handles[h]) != targets.row(static_cast<Eigen::Index>(h)))
      fail("handle " + std::to_string(sets.handles[h]) + " is not on its target");
  for (int s : sets.statics)
    if (r.positions.row(s) != rest.row(s)) fail("static vertex " + std::to_string(s) + " moved");
}

void run(FuzzedDataProvider& in) {
  const test::TestMesh m = in.ConsumeIntegralInRange<int>(0, 2) != 0 ? random_mesh(in) : edited_real_mesh(in);
  const int n = static_cast<int>(m.V.rows());
  const Domain domain = in.ConsumeBool() ? Domain::Edge : Domain::Primal;
  Deformer d(m.V, m.F, domain, /*clamp_negative_weights=*/in.ConsumeIntegralInRange<int>(0, 3) != 0);

  ConstraintSets sets;
  sets.handles = index_set(in, n, 8);
  sets.statics = index_set(in, n, 8);
  if (in.ConsumeBool()) sets.roi = index_set(in, n, 64);
  d.set_constraints(sets);
  if (in.ConsumeBool()) {
    d.set_stiffness(in.ConsumeBool() ? in.ConsumeProbability<double>() : in.ConsumeFloatingPoint<double>());
  } else {
    Eigen::VectorXd lambda(n);
    for (int v = 0; v < n; ++v) lambda(v) = in.ConsumeIntegralInRange<int>(0, 20) == 0 ? -0.5 : in.ConsumeProbability<double>();
    d.set_stiffness(lambda);
  }
  for (int round = 0; round < 2; ++round) {  // a second solve warm-starts from the first
    const size_t wrong_count = in.ConsumeIntegralInRange<int>(0, 7) == 0 ? 1 : 0;
    RowMatrixX3d targets(static_cast<Eigen::Index>(sets.handles.size() + wrong_count), 3);
    for (Eigen::Index h = 0; h < targets.rows(); ++h) {
      const int v = h < static_cast<Eigen::Index>(sets.handles.size()) ? sets.handles[static_cast<size_t>(h)] : 0;
      for (int c = 0; c < 3; ++c) targets(h, c) = (v >= 0 && v < n ? m.V(v, c) : 0.0) + coordinate(in);
    }
    SolveOptions o;
    o.max_iterations = in.ConsumeIntegralInRange<int>(0, 12);
    o.tolerance = in.ConsumeBool() ? 1e-4 : in.ConsumeFloatingPoint<double>();
    o.warm_start = in.ConsumeBool();
    if (in.ConsumeIntegralInRange<int>(0, 3) == 0) {
      RowMatrixX3d start = m.V;
      for (int v = 0; v < n; ++v) start.row(v) += Eigen::RowVector3d(coordinate(in), 0.0, 0.0);
      o.initial = start;
    }
    try {
      const SolveResult r = d.solve(targets, o);
      check_result(r, m.V, sets, targets);
      compute_metrics(m.V, m.F, r.positions, sets.handles, targets);
    } catch (const std::invalid_argument&) {
    } catch (const std::out_of_range&) {
    } catch (const FactorizationError&) {
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider in(data, size);
  try {
    run(in);
  } catch (const std::invalid_argument&) {  // the documented errors; anything else escapes
  } catch (const std::out_of_range&) {       // and libFuzzer reports it as a crash
  } catch (const FactorizationError&) {
  }
  return 0;
}
