#include "system/constrained_system.h"

#include "mesh/stiffness.h"
#include "local_fit/term_shares.h"

#include <algorithm>
#include <deque>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

#include "base/errors.h"
#include "mesh/mesh_checks.h"
#include "mesh/region_by_distance.h"

namespace edgedeform {

namespace {

// Free components that touch no constrained vertex have nothing to hold them: they stay at
// rest (their system would be singular). Returns how many vertices were pinned that way.
int pin_unanchored_components(const VertexNeighbours& neighbours, std::vector<VertexRole>& role, int& n_components) {
  const int n = static_cast<int>(role.size());
  std::vector<int> component(static_cast<size_t>(n), -1);
  int pinned = 0;
  n_components = 0;
  std::vector<int> members;
  for (int seed = 0; seed < n; ++seed) {
    if (role[static_cast<size_t>(seed)] != kFree || component[static_cast<size_t>(seed)] >= 0) continue;
    bool anchored = false;
    members.clear();
    std::deque<int> queue{seed};
    component[static_cast<size_t>(seed)] = seed;
    while (!queue.empty()) {
      const int v = queue.front();
      queue.pop_front();
      members.push_back(v);
      neighbours.for_each(v, [&](int u) {
        if (role[static_cast<size_t>(u)] != kFree) {
          anchored = true;
        } else if (component[static_cast<size_t>(u)] < 0) {
          component[static_cast<size_t>(u)] = seed;
          queue.push_back(u);
        }
      });
    }
    if (!anchored) {
      for (int v : members) role[static_cast<size_t>(v)] = kAtRest;
      pinned += static_cast<int>(members.size());
      ++n_components;
    }
  }
  return pinned;
}

// The region of interest as a list: sets.roi, or the vertices within sets.roi_radius of a
// handle. Either way the roles below come from one list, so a radius and the region it
// picks, given as roi, are the same problem bit for bit.
std::optional<std::vector<int>> region_of_interest(const RowMatrixX3d& rest, const VertexNeighbours& neighbours,
                                                   const ConstraintSets& sets) {
  if (sets.roi_radius && sets.roi)
    throw std::invalid_argument("roi and roi_radius both given: pass the region as one or the other");
  if (sets.roi_connected && !sets.roi_radius)
    throw std::invalid_argument("roi_connected needs roi_radius (the distance over the surface)");
  if (sets.roi_from && !sets.roi_radius)
    throw std::invalid_argument("roi_from needs roi_radius (the distance measured from it)");
  if (!sets.roi_radius) return sets.roi;
  if (sets.roi_from) {
    check_index_set(*sets.roi_from, static_cast<int>(rest.rows()), "roi_from");
    if (sets.roi_from->empty()) throw std::invalid_argument("roi_from is empty: give the vertices to measure from, or None");
  }
  return vertices_within_distance(rest, neighbours, sets.roi_from ? *sets.roi_from : sets.handles, *sets.roi_radius,
                                  sets.roi_connected);
}

std::vector<VertexRole> checked_roles(int n, const std::vector<bool>& referenced, const RowMatrixX3d& rest,
                                      const VertexNeighbours& neighbours, const ConstraintSets& sets,
                                      std::vector<std::string>& warnings) {
  check_index_set(sets.handles, n, "handles");
  check_index_set(sets.statics, n, "static");
  if (sets.handles.empty()) throw std::invalid_argument("handles is empty: at least one handle vertex is needed");
  const std::optional<std::vector<int>> roi = region_of_interest(rest, neighbours, sets);
  std::vector<VertexRole> role(static_cast<size_t>(n), kFree);
  for (int v : sets.handles) role[static_cast<size_t>(v)] = kHandle;
  for (int v : sets.statics) {
    if (role[static_cast<size_t>(v)] == kHandle)
      throw std::invalid_argument("vertex " + std::to_string(v) + " is in both handles and static");
    role[static_cast<size_t>(v)] = kAtRest;
  }
  if (roi) {
    check_index_set(*roi, n, "roi");
    std::vector<bool> in_roi(static_cast<size_t>(n), false);
    for (int v : *roi) in_roi[static_cast<size_t>(v)] = true;
    for (int v = 0; v < n; ++v)
      if (!in_roi[static_cast<size_t>(v)] && role[static_cast<size_t>(v)] == kFree) role[static_cast<size_t>(v)] = kAtRest;
  }
  int unreferenced = 0;
  for (int v = 0; v < n; ++v)
    if (!referenced[static_cast<size_t>(v)] && role[static_cast<size_t>(v)] == kFree) {
      role[static_cast<size_t>(v)] = kAtRest;
      ++unreferenced;
    }
  if (unreferenced > 0)
    warnings.push_back(std::to_string(unreferenced) + " vertices are not used by any face and stay at rest");
  return role;
}

// Whether any vertex would be free with an unbounded radius (every vertex in space, or every
// one reachable over the surface from the radius's seeds).
bool some_radius_frees_a_vertex(int n, const std::vector<bool>& referenced, const RowMatrixX3d& rest,
                                const VertexNeighbours& neighbours, ConstraintSets sets) {
  sets.roi_radius = std::numeric_limits<double>::max();
  std::vector<std::string> warnings;
  std::vector<VertexRole> role = checked_roles(n, referenced, rest, neighbours, sets, warnings);
  int n_components = 0;
  pin_unanchored_components(neighbours, role, n_components);
  return std::find(role.begin(), role.end(), kFree) != role.end();
}

// An explicit roi may leave nothing free (the solve then only places the handles); a radius
// that does is almost surely too small for the mesh, so it is an error that says so, or
// says that no radius would do when every vertex it could reach is held.
std::string no_free_vertex_message(const ConstraintSets& sets, bool a_larger_radius_helps) {
  std::ostringstream msg;
  msg << "no free vertex within roi_radius " << *sets.roi_radius << (sets.roi_connected ? " over the surface" : "")
      << (sets.roi_from ? " of roi_from" : " of the handles") << ": ";
  if (a_larger_radius_helps)
    msg << "increase the radius";
  else
    msg << "every vertex " << (sets.roi_connected ? "connected to them" : "of the mesh")
        << " is a handle or static (or touches no face, or no handle or static vertex), so no radius frees one";
  return msg.str();
}

void require_jacobians(const ConstrainedSystem& sys) {
  if (!sys.has_jacobians)
    throw std::logic_error("the constrained system has no J1, J2: assemble the system it was restricted from");
}

}  // namespace

ConstrainedSystem build_constrained_system(const NodeGraph& g, const RowMatrixX3d& rest,
                                           const VertexNeighbours& neighbours, const std::vector<bool>& referenced,
                                           const ConstraintSets& sets) {
  ConstrainedSystem sys = constrained_layout(g, rest, neighbours, referenced, sets);
  add_jacobians(sys);
  return sys;
}

ConstrainedSystem constrained_layout(const NodeGraph& g, const RowMatrixX3d& rest, const VertexNeighbours& neighbours,
                                     const std::vector<bool>& referenced, const ConstraintSets& sets) {
  if (neighbours.n_vertices() != g.n_vertices)
    throw std::logic_error("constrained_layout: the mesh incidence and the graph have different vertex counts");
  return layout_on(GraphPart{&g, &rest}, vertex_roles(rest, neighbours, referenced, sets), sets);
}

VertexRoles vertex_roles(const RowMatrixX3d& rest, const VertexNeighbours& neighbours, const std::vector<bool>& referenced,
                         const ConstraintSets& sets) {
  VertexRoles out;
  const int n = static_cast<int>(rest.rows());
  out.role = checked_roles(n, referenced, rest, neighbours, sets, out.warnings);
  int n_components = 0;
  const int pinned = pin_unanchored_components(neighbours, out.role, n_components);
  if (sets.roi_radius && std::find(out.role.begin(), out.role.end(), kFree) == out.role.end())
    throw NoFreeVertexError(
        no_free_vertex_message(sets, some_radius_frees_a_vertex(n, referenced, rest, neighbours, sets)));
  if (pinned > 0)
    out.warnings.push_back(std::to_string(pinned) + " free vertices in " + std::to_string(n_components) +
                           " component(s) touch no handle or static vertex and stay at rest");
  for (int v = 0; v < n; ++v)
    if (out.role[static_cast<size_t>(v)] == kFree) out.free_vertices.push_back(v);
  return out;
}

ConstrainedSystem layout_on(const GraphPart& part, VertexRoles roles, const ConstraintSets& sets) {
  const NodeGraph& g = *part.graph;
  const std::vector<VertexRole>& role = roles.role;
  ConstrainedSystem sys;
  const int n = static_cast<int>(role.size());
  sys.n_vertices = n;
  sys.similarity_floor = similarity_floor(g.domain);
  sys.warnings = std::move(roles.warnings);
  sys.handles = sets.handles;

  // Local vertex ids: free vertices first, then the fixed ones the terms touch.
  std::vector<int> local(static_cast<size_t>(n), -1);
  sys.free_vertices = std::move(roles.free_vertices);
  for (size_t k = 0; k < sys.free_vertices.size(); ++k) local[static_cast<size_t>(sys.free_vertices[k])] = static_cast<int>(k);
  const int nf = sys.n_free();

  // Active terms: nodes whose own or neighbours' positions depend on a free vertex. Node ids
  // below are the part's; the system keeps the mesh's.
  auto node_has_free = [&](int i) {
    return role[static_cast<size_t>(part.mesh_vertex(g.node_vertices(i, 0)))] == kFree ||
           role[static_cast<size_t>(part.mesh_vertex(g.node_vertices(i, 1)))] == kFree;
  };
  std::vector<char> touches(static_cast<size_t>(g.n_nodes), 0);
  for (int i = 0; i < g.n_nodes; ++i) {
    if (!node_has_free(i)) continue;
    touches[static_cast<size_t>(i)] = 1;
    for (int k = g.offsets[static_cast<size_t>(i)]; k < g.offsets[static_cast<size_t>(i) + 1]; ++k)
      touches[static_cast<size_t>(g.adjacency[static_cast<size_t>(k)])] = 1;
  }
  std::vector<int> stencil_index(static_cast<size_t>(g.n_nodes), -1), part_terms, part_stencil;
  for (int i = 0; i < g.n_nodes; ++i)
    if (touches[static_cast<size_t>(i)]) {
      stencil_index[static_cast<size_t>(i)] = static_cast<int>(part_terms.size());
      part_terms.push_back(i);
    }
  part_stencil = part_terms;
  for (int i : part_terms)
    for (int k = g.offsets[static_cast<size_t>(i)]; k < g.offsets[static_cast<size_t>(i) + 1]; ++k) {
      const int j = g.adjacency[static_cast<size_t>(k)];
      if (stencil_index[static_cast<size_t>(j)] < 0) {
        stencil_index[static_cast<size_t>(j)] = static_cast<int>(part_stencil.size());
        part_stencil.push_back(j);
      }
    }
  const int n_stencil = static_cast<int>(part_stencil.size());
  sys.stencil_node_vertices.resize(n_stencil, 2);
  for (int s = 0; s < n_stencil; ++s)
    for (int c = 0; c < 2; ++c) {
      const int v = part.mesh_vertex(g.node_vertices(part_stencil[static_cast<size_t>(s)], c));
      if (local[static_cast<size_t>(v)] < 0) {
        local[static_cast<size_t>(v)] = nf + static_cast<int>(sys.fixed_vertices.size());
        sys.fixed_vertices.push_back(v);
      }
      sys.stencil_node_vertices(s, c) = local[static_cast<size_t>(v)];
    }
  sys.stencil = build_stencil(g, *part.rest, part_terms, stencil_index);
  sys.rest_scale = sys.stencil.rest_norm.sum();
  for (int& i : part_stencil) i = part.mesh_node(i);
  sys.term_nodes.assign(part_stencil.begin(), part_stencil.begin() + static_cast<std::ptrdiff_t>(part_terms.size()));
  sys.stencil_nodes = std::move(part_stencil);
  return sys;
}

void stencil_node_positions(const ConstrainedSystem& sys, const RowMatrixX3d& x_local, RowMatrixX3d& p) {
  const Eigen::Index n = sys.stencil_node_vertices.rows();
  p.resize(n, 3);
  for (Eigen::Index s = 0; s < n; ++s)
    p.row(s) = 0.5 * (x_local.row(sys.stencil_node_vertices(s, 0)) + x_local.row(sys.stencil_node_vertices(s, 1)));
}

void add_jacobians(ConstrainedSystem& sys) {
  // J1 (arc differences), J2 (Laplacian rows) in local ids.
  const NodeStencil& st = sys.stencil;
  const int T = st.n_terms, n_arcs = st.n_arcs(), nf = sys.n_free(), nc = sys.n_fixed();

  std::vector<Eigen::Triplet<double>> j1, j2;
  j1.reserve(static_cast<size_t>(4 * n_arcs));
  j2.reserve(static_cast<size_t>(4 * n_arcs));
  for (int t = 0; t < T; ++t) {
    for (int a = st.offsets[static_cast<size_t>(t)]; a < st.offsets[static_cast<size_t>(t) + 1]; ++a) {
      const double w = st.weight[static_cast<size_t>(a)];
      if (w == 0.0) continue;  // a clamped arc: its row stays empty
      const int j = st.neighbour[static_cast<size_t>(a)];
      for (int c = 0; c < 2; ++c) {  // p_i - p_j, each node the mean of its two vertex slots
        j1.emplace_back(a, sys.stencil_node_vertices(t, c), 0.5);
        j1.emplace_back(a, sys.stencil_node_vertices(j, c), -0.5);
        j2.emplace_back(t, sys.stencil_node_vertices(t, c), 0.5 * w);
        j2.emplace_back(t, sys.stencil_node_vertices(j, c), -0.5 * w);
      }
    }
  }
  SparseMatrix J1(n_arcs, nf + nc), J2(T, nf + nc);
  J1.setFromTriplets(j1.begin(), j1.end());
  J2.setFromTriplets(j2.begin(), j2.end());
  J1.prune(0.0);  // in the edge domain the shared vertex cancels exactly
  J2.prune(0.0);
  sys.J1f = J1.leftCols(nf);
  sys.J1c = J1.rightCols(nc);
  sys.J2f = J2.leftCols(nf);
  sys.J2c = J2.rightCols(nc);
  sys.has_jacobians = true;
}

std::vector<int> free_vertex_order(const ConstrainedSystem& sys, const std::vector<int>& rank) {
  for (int v : sys.free_vertices)
    if (static_cast<size_t>(v) >= rank.size() || rank[static_cast<size_t>(v)] < 0) return {};
  std::vector<int> order(static_cast<size_t>(sys.n_free()));
  for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return rank[static_cast<size_t>(sys.free_vertices[static_cast<size_t>(a)])] <
           rank[static_cast<size_t>(sys.free_vertices[static_cast<size_t>(b)])];
  });
  return order;
}

RotationOperator rotation_operator(const ConstrainedSystem& sys) {
  require_jacobians(sys);
  // H at lambda = 1 (h_R, the 1-form columns) and lambda = 0 (h_T, the Laplacian columns),
  // block (v, t) = sum over t's arcs a of J1f(a,v) w_a e0_a, and J2f(t,v) delta0_t. Gathered
  // term by term (a term touches a handful of vertices), then sorted into rows by counting.
  const NodeStencil& st = sys.stencil;
  const int T = st.n_terms, nf = sys.n_free();
  const SparseMatrix J1fT = sys.J1f.transpose(), J2fT = sys.J2f.transpose();
  std::vector<int> block_vertex, block_term;
  std::vector<double> block_coef;  // 6 per block
  std::vector<int> row_count(static_cast<size_t>(nf) + 1, 0);
  for (int t = 0; t < T; ++t) {
    const size_t first = block_vertex.size();
    auto block = [&](int v) -> double* {  // this term's block of vertex v, made on first use
      for (size_t b = first; b < block_vertex.size(); ++b)
        if (block_vertex[b] == v) return &block_coef[6 * b];
      block_vertex.push_back(v);
      block_term.push_back(t);
      block_coef.insert(block_coef.end(), 6, 0.0);
      ++row_count[static_cast<size_t>(v) + 1];
      return &block_coef[block_coef.size() - 6];
    };
    for (int a = st.offsets[static_cast<size_t>(t)]; a < st.offsets[static_cast<size_t>(t) + 1]; ++a) {
      const double w = st.weight[static_cast<size_t>(a)];
      if (w == 0.0) continue;
      for (SparseMatrix::InnerIterator it(J1fT, a); it; ++it) {
        double* h = block(static_cast<int>(it.row()));
        for (int k = 0; k < 3; ++k) h[k] += w * it.value() * st.rest_edge(a, k);
      }
    }
    for (SparseMatrix::InnerIterator it(J2fT, t); it; ++it) {
      double* h = block(static_cast<int>(it.row()));
      for (int k = 0; k < 3; ++k) h[3 + k] += it.value() * st.rest_laplacian(t, k);
    }
  }
  // Rows in vertex order; within a row, terms ascend (blocks were made in term order).
  for (int v = 0; v < nf; ++v) row_count[static_cast<size_t>(v) + 1] += row_count[static_cast<size_t>(v)];
  std::vector<int> cursor(row_count.begin(), row_count.end() - 1), term(block_term.size());
  std::vector<double> coef(block_coef.size());
  for (size_t b = 0; b < block_vertex.size(); ++b) {
    const auto slot = static_cast<size_t>(cursor[static_cast<size_t>(block_vertex[b])]++);
    term[slot] = block_term[b];
    std::copy_n(&block_coef[6 * b], 6, &coef[6 * slot]);
  }
  return RotationOperator(std::move(row_count), std::move(term), std::move(coef), T);
}

AssembledSystem assemble_system(const ConstrainedSystem& sys, const Eigen::VectorXd& vertex_lambda) {
  AssembledSystem out;
  out.H = rotation_operator(sys);
  update_stiffness(out, sys, vertex_lambda);
  return out;
}

Eigen::VectorXd term_stiffness(const ConstrainedSystem& sys, const Eigen::VectorXd& vertex_lambda) {
  if (vertex_lambda.size() != sys.n_vertices)
    throw std::logic_error("term_stiffness: " + std::to_string(vertex_lambda.size()) + " lambdas for " +
                           std::to_string(sys.n_vertices) + " vertices");
  auto mesh_vertex = [&](int local) {
    return local < sys.n_free() ? sys.free_vertices[static_cast<size_t>(local)]
                                : sys.fixed_vertices[static_cast<size_t>(local - sys.n_free())];
  };
  Eigen::VectorXd lambda(sys.n_terms());
  for (int t = 0; t < sys.n_terms(); ++t)  // node_stiffness's sum, in its order
    lambda(t) = 0.5 * (vertex_lambda(mesh_vertex(sys.stencil_node_vertices(t, 0))) +
                       vertex_lambda(mesh_vertex(sys.stencil_node_vertices(t, 1))));
  return lambda;
}

void set_term_stiffness(AssembledSystem& out, const ConstrainedSystem& sys, const Eigen::VectorXd& vertex_lambda) {
  out.term_lambda = term_stiffness(sys, vertex_lambda);
  out.term_similar = similarity_share(out.term_lambda, sys.similarity_floor);
  out.laplacian_term = (out.term_lambda.array() < 1.0).any();
  out.H.set_term_lambda(out.term_lambda, out.term_similar);
}

bool assembled_at(const AssembledSystem& as, const ConstrainedSystem& sys, const Eigen::VectorXd& vertex_lambda) {
  return as.term_lambda.size() == sys.n_terms() && as.term_lambda == term_stiffness(sys, vertex_lambda);
}

void update_stiffness(AssembledSystem& out, const ConstrainedSystem& sys, const Eigen::VectorXd& vertex_lambda) {
  require_jacobians(sys);
  const NodeStencil& st = sys.stencil;
  const int T = st.n_terms;
  set_term_stiffness(out, sys, vertex_lambda);

  // 1-form arcs weigh lambda_t + phi_t (rigid and similarity shares), the Laplacian 1 - both.
  Eigen::VectorXd w1(st.n_arcs());
  for (int t = 0; t < T; ++t)
    for (int a = st.offsets[static_cast<size_t>(t)]; a < st.offsets[static_cast<size_t>(t) + 1]; ++a)
      w1(a) = term_shares(out.term_lambda(t), out.term_similar(t)).one_form() * st.weight[static_cast<size_t>(a)];
  Eigen::VectorXd w2(T);
  for (int t = 0; t < T; ++t) w2(t) = term_shares(out.term_lambda(t), out.term_similar(t)).smooth;

  // The J1 term is kept even when every W1 is 0: its pattern lies inside the J2 term's, so
  // the symbolic analysis survives any change of lambda below 1.
  const SparseMatrix B1 = SparseMatrix(sys.J1f.transpose()) * w1.asDiagonal();
  out.A = B1 * sys.J1f;
  out.K_fixed = B1 * sys.J1c;
  if (out.laplacian_term) {
    const SparseMatrix B2 = SparseMatrix(sys.J2f.transpose()) * w2.asDiagonal();
    out.A += B2 * sys.J2f;
    out.K_fixed += B2 * sys.J2c;
  }
}

}  // namespace edgedeform
