// Test matrices for the Cholesky tests: grid Laplacians, random SPD matrices,
// the third-party SPD suite (CHOLMOD triplet, Matrix Market, Rutherford-Boeing
// files in tests/data), and conversion to Eigen for independent solves.
#pragma once
#include <Eigen/Sparse>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "locus/sparse_matrix.hpp"

namespace locus::test {

// `count` distinct indices of 0..n-1 in random order (all of them if count >= n).
inline std::vector<int32_t> random_set(int32_t n, int32_t count, std::mt19937_64& rng) {
  std::vector<int32_t> all(n);
  for (int32_t i = 0; i < n; ++i) all[i] = i;
  std::shuffle(all.begin(), all.end(), rng);
  all.resize(std::min(count, n));
  return all;
}


// 5-point Laplacian of an nx x ny grid plus shift * I (SPD for shift > 0).
inline CscMatrix grid_laplacian(int nx, int ny, double shift) {
  std::vector<int32_t> I, J;
  std::vector<double> V;
  auto id = [nx](int x, int y) { return y * nx + x; };
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      I.push_back(id(x, y)); J.push_back(id(x, y)); V.push_back(4.0 + shift);
      if (x + 1 < nx) { I.push_back(id(x + 1, y)); J.push_back(id(x, y)); V.push_back(-1.0); }
      if (y + 1 < ny) { I.push_back(id(x, y + 1)); J.push_back(id(x, y)); V.push_back(-1.0); }
    }
  return lower_from_triplets(nx * ny, I, J, V);
}

// Random sparse SPD: random symmetric pattern with ~deg off-diagonals per row,
// values in [-1, 1], diagonal = row sum of |offdiag| + 1 (strictly diagonally dominant).
inline CscMatrix random_spd(int32_t n, int deg, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int32_t> pick(0, n - 1);
  std::uniform_real_distribution<double> val(-1.0, 1.0);
  std::vector<int32_t> I, J;
  std::vector<double> V;
  std::vector<double> diag(n, 1.0);
  for (int32_t i = 0; i < n; ++i)
    for (int d = 0; d < deg / 2 + 1; ++d) {
      const int32_t j = pick(rng);
      if (j == i) continue;
      const double v = val(rng);
      I.push_back(i); J.push_back(j); V.push_back(v);
      diag[i] += std::abs(v);
      diag[j] += std::abs(v);
    }
  for (int32_t i = 0; i < n; ++i) { I.push_back(i); J.push_back(i); V.push_back(diag[i]); }
  return lower_from_triplets(n, I, J, V);
}

// Full symmetric Eigen matrix from a lower-stored one.
inline Eigen::SparseMatrix<double> to_eigen(const CscMatrix& A) {
  std::vector<Eigen::Triplet<double>> t;
  for (int32_t j = 0; j < A.ncols; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      t.emplace_back(A.rowind[p], j, A.values[p]);
      if (A.rowind[p] != j) t.emplace_back(j, A.rowind[p], A.values[p]);
    }
  Eigen::SparseMatrix<double> E(A.nrows, A.ncols);
  E.setFromTriplets(t.begin(), t.end());
  return E;
}

// Lower-stored matrix from a full symmetric Eigen one.
inline CscMatrix from_eigen_lower(const Eigen::SparseMatrix<double>& E) {
  std::vector<int32_t> I, J;
  std::vector<double> V;
  for (int k = 0; k < E.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(E, k); it; ++it)
      if (it.row() >= it.col()) {
        I.push_back(static_cast<int32_t>(it.row()));
        J.push_back(static_cast<int32_t>(it.col()));
        V.push_back(it.value());
      }
  return lower_from_triplets(static_cast<int32_t>(E.rows()), I, J, V);
}

// CHOLMOD triplet (.tri: "nrow ncol nnz stype") or Matrix Market (.mtx) text; 1-based.
// Keeps a symmetric matrix: for "general" files only the lower triangle is read.
inline CscMatrix read_triplet_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::string line;
  bool general = false, header_done = false;
  int64_t nrow = 0, ncol = 0, nnz = 0;
  std::vector<int32_t> I, J;
  std::vector<double> V;
  while (std::getline(in, line)) {
    if (line.rfind("%%MatrixMarket", 0) == 0) { general = line.find("general") != std::string::npos; continue; }
    if (line.empty() || line[0] == '%') continue;
    std::istringstream ss(line);
    if (!header_done) { ss >> nrow >> ncol >> nnz; header_done = true; continue; }
    int64_t i, j;
    double v;
    if (!(ss >> i >> j >> v)) continue;
    if (general && i < j) continue;
    I.push_back(static_cast<int32_t>(i - 1)); J.push_back(static_cast<int32_t>(j - 1)); V.push_back(v);
  }
  if (nrow != ncol) throw std::runtime_error(path + ": not square");
  return lower_from_triplets(static_cast<int32_t>(nrow), I, J, V);
}

// Rutherford-Boeing "rsa" (real symmetric assembled, lower triangle by columns),
// fixed-width fields as given by the Fortran formats in the header.
inline CscMatrix read_rsa_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::string title, l2, l3, l4;
  std::getline(in, title); std::getline(in, l2); std::getline(in, l3); std::getline(in, l4);
  std::istringstream s3(l3.substr(14));
  int64_t nrow, ncol, nnz;
  s3 >> nrow >> ncol >> nnz;
  auto width = [](const std::string& fmt) {  // "(16I5)" -> 5, "(4E20.12)" -> 20
    const size_t p = fmt.find_first_of("IEDF");
    return std::stoi(fmt.substr(p + 1));
  };
  std::istringstream s4(l4);
  std::string fp, fi, fv;
  s4 >> fp >> fi >> fv;
  auto read_fixed = [&in](int w, int64_t count, auto&& sink) {
    std::string line;
    int64_t got = 0;
    while (got < count && std::getline(in, line))
      for (size_t p = 0; p + w <= line.size() + (w - 1) && got < count; p += w) {
        std::string field = line.substr(p, w);
        if (field.find_first_not_of(' ') == std::string::npos) break;
        for (char& c : field) if (c == 'D' || c == 'd') c = 'E';
        sink(field);
        ++got;
      }
  };
  std::vector<int64_t> colptr;
  std::vector<int32_t> rowind;
  std::vector<double> vals;
  read_fixed(width(fp), ncol + 1, [&](const std::string& f) { colptr.push_back(std::stoll(f)); });
  read_fixed(width(fi), nnz, [&](const std::string& f) { rowind.push_back(std::stoi(f)); });
  read_fixed(width(fv), nnz, [&](const std::string& f) { vals.push_back(std::stod(f)); });
  std::vector<int32_t> I, J;
  std::vector<double> V;
  for (int64_t j = 0; j < ncol; ++j)
    for (int64_t p = colptr[j] - 1; p < colptr[j + 1] - 1; ++p) {
      I.push_back(rowind[p] - 1); J.push_back(static_cast<int32_t>(j)); V.push_back(vals[p]);
    }
  return lower_from_triplets(static_cast<int32_t>(nrow), I, J, V);
}

}  // namespace locus::test
