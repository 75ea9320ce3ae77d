// Small meshes for the C++ tests: procedural ones, and an OFF reader for tests/data.
#pragma once

#include <cmath>
#include <algorithm>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/types.h"

namespace edgedeform::test {

struct TestMesh {
  RowMatrixX3d V;
  RowMatrixX3i F;
};

// An nx x ny grid on [0,1]^2 (z = bump * sin), split into triangles along alternating diagonals.
inline TestMesh grid(int nx, int ny, double bump = 0.0) {
  TestMesh m;
  m.V.resize(nx * ny, 3);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = double(i) / (nx - 1), y = double(j) / (ny - 1);
      m.V.row(j * nx + i) << x, y, bump * std::sin(3.0 * x) * std::cos(2.0 * y);
    }
  m.F.resize(2 * (nx - 1) * (ny - 1), 3);
  int f = 0;
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
      if ((i + j) % 2 == 0) {
        m.F.row(f++) << a, b, d;
        m.F.row(f++) << a, d, c;
      } else {
        m.F.row(f++) << a, b, c;
        m.F.row(f++) << b, d, c;
      }
    }
  return m;
}

inline TestMesh tetrahedron() {
  TestMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.F.resize(4, 3);
  m.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  return m;
}

// A grid(nx, ny) with a fin: a vertical strip of triangles standing on the grid's middle row
// of edges, so that each of those edges is shared by three faces (two of the grid, one of
// the fin). Fin vertices are appended after the grid's.
inline TestMesh grid_with_fin(int nx, int ny) {
  TestMesh m = grid(nx, ny);
  const int row = ny / 2, n0 = static_cast<int>(m.V.rows()), f0 = static_cast<int>(m.F.rows());
  m.V.conservativeResize(n0 + nx, 3);
  for (int i = 0; i < nx; ++i) m.V.row(n0 + i) << double(i) / (nx - 1), double(row) / (ny - 1), 0.3;
  m.F.conservativeResize(f0 + 2 * (nx - 1), 3);
  for (int i = 0; i + 1 < nx; ++i) {
    const int a = row * nx + i, b = a + 1, c = n0 + i, d = c + 1;
    m.F.row(f0 + 2 * i) << a, b, d;
    m.F.row(f0 + 2 * i + 1) << a, d, c;
  }
  return m;
}

// A fin (edges of three faces), shuffled vertex ids, a vertex no face uses, a face given twice.
inline TestMesh messy_mesh() {
  TestMesh m = grid_with_fin(7, 6);
  const int n = static_cast<int>(m.V.rows());
  std::vector<int> id(static_cast<size_t>(n));
  for (int v = 0; v < n; ++v) id[static_cast<size_t>(v)] = v;
  std::shuffle(id.begin(), id.end(), std::mt19937(5));
  RowMatrixX3d V(n + 1, 3);
  for (int v = 0; v < n; ++v) V.row(id[static_cast<size_t>(v)]) = m.V.row(v);
  V.row(n) << 9.0, 9.0, 9.0;  // unreferenced
  RowMatrixX3i F(m.F.rows() + 1, 3);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) F(f, k) = id[static_cast<size_t>(m.F(f, k))];
  F.row(m.F.rows()) = F.row(0);
  m.V = V;
  m.F = F;
  return m;
}

// Reads the vertex and triangle lines of an OFF/COFF file in tests/data.
inline TestMesh read_off(const std::string& name) {
  std::ifstream in(std::string(EDGEDEFORM_TEST_DATA) + "/" + name);
  if (!in) throw std::runtime_error("cannot open test mesh " + name);
  std::string header;
  in >> header;
  int n = 0, m = 0, e = 0;
  in >> n >> m >> e;
  TestMesh mesh;
  mesh.V.resize(n, 3);
  std::string line;
  std::getline(in, line);
  for (int v = 0; v < n; ++v) {
    std::getline(in, line);
    std::istringstream s(line);
    s >> mesh.V(v, 0) >> mesh.V(v, 1) >> mesh.V(v, 2);
  }
  mesh.F.resize(m, 3);
  for (int f = 0; f < m; ++f) {
    int k = 0;
    in >> k >> mesh.F(f, 0) >> mesh.F(f, 1) >> mesh.F(f, 2);
    std::getline(in, line);
  }
  return mesh;
}

}  // namespace edgedeform::test
