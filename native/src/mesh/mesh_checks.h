// Validation of user meshes and index sets, with messages that name the problem.
#pragma once

#include <string>
#include <vector>

#include "base/types.h"

namespace edgedeform {

// Throws std::invalid_argument for an empty mesh or non-finite coordinates,
// std::out_of_range for a face index outside [0, n), std::invalid_argument for a face that
// repeats a vertex.
void check_mesh(const RowMatrixX3d& V, const RowMatrixX3i& F);

// Throws std::invalid_argument naming the shape when a connected piece of the mesh has no
// face the solver can use: all its vertices at one point, or every face of zero area (a
// needle with every angle's sine below kSinFloor). Call after check_mesh.
void check_geometry(const RowMatrixX3d& V, const RowMatrixX3i& F);

// How far (per coordinate) from the mesh's centre positions may lie before the energies,
// sums of w * |d|^2 over arcs of total weight `total_weight`, could overflow a double.
double largest_safe_distance(double total_weight);
// Throws std::invalid_argument naming `what`[row] if a row of X lies farther than `limit`
// from `center` in some coordinate (or is non-finite).
void check_distance(const RowMatrixX3d& X, const Eigen::RowVector3d& center, double limit, const char* what);

// Throws std::out_of_range if an entry of `indices` (named `what`) is outside [0, n),
// std::invalid_argument if one repeats.
void check_index_set(const std::vector<int>& indices, int n, const char* what);

// Throws std::invalid_argument if `X` (named `what`) has a non-finite entry.
void check_finite(const RowMatrixX3d& X, const char* what);

// Per vertex, a label of its connected piece (vertices joined through faces share one; the
// label is the piece's root vertex). Unreferenced vertices are pieces of their own.
std::vector<int> connected_pieces(const RowMatrixX3i& F, int n);

// True for each vertex used by at least one face.
std::vector<bool> referenced_vertices(const RowMatrixX3i& F, int n);

}  // namespace edgedeform
