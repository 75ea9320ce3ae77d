// CGAL Surface_mesh_deformation on one benchmark problem (mesh + handles + static vertices),
// timed the way bench/peers/trajectory.py times the Python peers:
//   precompute  = deformation object + ROI + control vertices + preprocess() (factorization)
//   ms/it       = wall time of deform(block, 0) / block, `repeat` times
//   reference   = its own converged shape: one iteration at a time until the estimated
//                 distance to the fixed point (last move * rate / (1 - rate), rate = median
//                 ratio of the last five moves) is <= ref_tol * diag, or ref_iterations ran out
//   eps         = iterations from the start until every vertex is within eps * diag of it
// Prints one JSON object on stdout. Usage:
//   cgal_arap_bench MESH.off CONSTRAINTS.txt arap|spokes_and_rims
//       [ref_iterations ref_tol eps repeat block]
// CONSTRAINTS.txt: "diag D", "handles K" + K lines "index x y z", "static M" + M indices.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_deformation.h>
#include <CGAL/version.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using VD = Mesh::Vertex_index;

namespace {

struct Problem {
  double diag = 0;
  std::vector<std::size_t> handles;
  std::vector<Point> targets;
  std::vector<std::size_t> fixed;  // static vertices: control vertices kept at rest
};

Problem read_constraints(const std::string& path, std::size_t n) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open constraints file " + path);
  Problem p;
  std::string word;
  std::size_t count = 0;
  in >> word >> p.diag;
  if (word != "diag") throw std::runtime_error("constraints: expected 'diag'");
  in >> word >> count;
  if (word != "handles") throw std::runtime_error("constraints: expected 'handles'");
  for (std::size_t k = 0; k < count; ++k) {
    std::size_t i;
    double x, y, z;
    in >> i >> x >> y >> z;
    p.handles.push_back(i);
    p.targets.emplace_back(x, y, z);
  }
  in >> word >> count;
  if (word != "static") throw std::runtime_error("constraints: expected 'static'");
  for (std::size_t k = 0; k < count; ++k) {
    std::size_t i;
    in >> i;
    p.fixed.push_back(i);
  }
  if (!in) throw std::runtime_error("constraints: file ended early");
  for (std::size_t i : p.handles)
    if (i >= n) throw std::out_of_range("constraints: handle index out of range");
  for (std::size_t i : p.fixed)
    if (i >= n) throw std::out_of_range("constraints: static index out of range");
  return p;
}

// CPU time of the whole process (all threads), ms: load from other processes hardly
// changes it, unlike wall time.
double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

std::vector<Point> positions(const Mesh& mesh) {
  std::vector<Point> x;
  x.reserve(mesh.number_of_vertices());
  for (VD v : mesh.vertices()) x.push_back(mesh.point(v));
  return x;
}

// Largest Euclidean distance between corresponding vertices.
double max_distance(const std::vector<Point>& a, const std::vector<Point>& b) {
  double d2 = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d2 = std::max(d2, CGAL::squared_distance(a[i], b[i]));
  return std::sqrt(d2);
}

// High-water mark of this process's resident memory (MB), from /proc/self/status.
double vm_hwm_mb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return -1;
}

// Estimated distance to the fixed point (/ diag) from the last moves; < 0 while the tail
// does not look contracting. Same rule as bench/peers/trajectory.py.
double distance_estimate(const std::vector<double>& r, std::size_t window = 5) {
  if (!r.empty() && r.back() == 0) return 0;
  if (r.size() <= window) return -1;
  std::vector<double> rates;
  for (std::size_t i = r.size() - window; i < r.size(); ++i)
    rates.push_back(r[i] / std::max(r[i - 1], 1e-300));
  const double rate = median(rates);
  return rate < 1 ? r.back() * rate / (1 - rate) : -1;
}

std::string json_list(const std::vector<double>& v) {
  std::ostringstream s;
  s << "[";
  for (std::size_t i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i];
  return s.str() + "]";
}

template <CGAL::Deformation_algorithm_tag TAG>
int run(Mesh& mesh, const Problem& p, int ref_iterations, double ref_tol, double eps, int repeat,
        int block, const char* name) {
  using Deformation = CGAL::Surface_mesh_deformation<Mesh, CGAL::Default, CGAL::Default, TAG>;
  const auto rest = positions(mesh);
  const std::vector<VD> verts(mesh.vertices().begin(), mesh.vertices().end());

  auto set_targets = [&](Deformation& dm) {
    for (std::size_t k = 0; k < p.handles.size(); ++k)
      dm.set_target_position(verts[p.handles[k]], p.targets[k]);
  };
  auto make = [&]() {
    auto dm = std::make_unique<Deformation>(mesh);
    dm->insert_roi_vertices(verts.begin(), verts.end());
    for (std::size_t i : p.handles) dm->insert_control_vertex(verts[i]);
    for (std::size_t i : p.fixed) dm->insert_control_vertex(verts[i]);
    if (!dm->preprocess()) throw std::runtime_error("CGAL preprocess() failed (rank-deficient system)");
    return dm;
  };

  std::vector<double> pre_ms, pre_cpu;
  std::unique_ptr<Deformation> dm;
  for (int r = 0; r < repeat; ++r) {
    dm.reset();
    const double c0 = cpu_ms();
    auto t0 = std::chrono::steady_clock::now();
    dm = make();
    pre_ms.push_back(ms_since(t0));
    pre_cpu.push_back(cpu_ms() - c0);
  }

  // Reference: its own converged shape, one iteration at a time from the rest shape.
  set_targets(*dm);
  std::vector<double> residuals;
  auto prev = rest;
  bool ref_converged = false;
  for (int it = 1; it <= ref_iterations; ++it) {
    dm->deform(1, 0.0);
    auto x = positions(mesh);
    residuals.push_back(max_distance(x, prev) / p.diag);
    prev.swap(x);
    const double est = distance_estimate(residuals);
    if (est >= 0 && est <= ref_tol) {
      ref_converged = true;
      break;
    }
  }
  const auto reference = prev;

  // Iterations until within eps * diag of the reference, again from the rest shape.
  dm->reset();
  set_targets(*dm);
  int eps_iterations = -1;
  for (int it = 1; it <= static_cast<int>(residuals.size()); ++it) {
    dm->deform(1, 0.0);
    if (max_distance(positions(mesh), reference) <= eps * p.diag) {
      eps_iterations = it;
      break;
    }
  }

  // Per iteration: blocks of `block` iterations (no energy evaluation: tolerance 0).
  std::vector<double> it_ms, it_cpu;
  for (int r = 0; r < repeat; ++r) {
    const double c0 = cpu_ms();
    auto t0 = std::chrono::steady_clock::now();
    dm->deform(block, 0.0);
    it_ms.push_back(ms_since(t0) / block);
    it_cpu.push_back((cpu_ms() - c0) / block);
  }

  std::ostringstream out;
  out.precision(10);
  out << "{\"method\": \"" << name << "\", \"version\": \"CGAL " << CGAL_VERSION_STR
      << "\", \"solver\": \"Eigen SparseLU (CGAL default)\", \"threads\": 1"
      << ", \"vertices\": " << rest.size()
      << ", \"precompute_ms\": " << median(pre_ms) << ", \"precompute_ms_all\": " << json_list(pre_ms)
      << ", \"precompute_cpu_ms\": " << median(pre_cpu)
      << ", \"ms_per_it\": " << median(it_ms) << ", \"ms_per_it_all\": " << json_list(it_ms)
      << ", \"cpu_ms_per_it\": " << median(it_cpu)
      << ", \"ref_iterations\": " << residuals.size()
      << ", \"ref_converged\": " << (ref_converged ? "true" : "false")
      << ", \"ref_error_estimate\": ";
  const double est = distance_estimate(residuals);
  if (est >= 0) out << est; else out << "null";
  out
      << ", \"residual_tail\": "
      << json_list(std::vector<double>(residuals.end() - std::min<std::size_t>(residuals.size(), 10),
                                       residuals.end()))
      << ", \"eps_iterations\": ";
  if (eps_iterations > 0) out << eps_iterations; else out << "null";
  out << ", \"vm_hwm_mb\": " << vm_hwm_mb() << "}";
  std::cout << out.str() << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::cerr << "usage: cgal_arap_bench MESH.off CONSTRAINTS.txt arap|spokes_and_rims "
                 "[ref_iterations ref_tol eps repeat block]\n";
    return 2;
  }
  try {
    const int ref_iterations = argc > 4 ? std::stoi(argv[4]) : 2000;
    const double ref_tol = argc > 5 ? std::stod(argv[5]) : 1e-4;
    const double eps = argc > 6 ? std::stod(argv[6]) : 1e-3;
    const int repeat = argc > 7 ? std::stoi(argv[7]) : 3;
    const int block = argc > 8 ? std::stoi(argv[8]) : 10;
    Mesh mesh;
    std::ifstream in(argv[1]);
    if (!in || !CGAL::IO::read_OFF(in, mesh) || mesh.is_empty())
      throw std::runtime_error(std::string("cannot read OFF mesh ") + argv[1]);
    const Problem p = read_constraints(argv[2], mesh.number_of_vertices());
    const std::string tag = argv[3];
    if (tag == "arap")
      return run<CGAL::ORIGINAL_ARAP>(mesh, p, ref_iterations, ref_tol, eps, repeat, block,
                                      "cgal_original_arap");
    if (tag == "spokes_and_rims")
      return run<CGAL::SPOKES_AND_RIMS>(mesh, p, ref_iterations, ref_tol, eps, repeat, block,
                                        "cgal_spokes_and_rims");
    throw std::invalid_argument("algorithm must be 'arap' or 'spokes_and_rims', got '" + tag + "'");
  } catch (const std::exception& e) {
    std::cerr << "cgal_arap_bench: " << e.what() << "\n";
    return 1;
  }
}
