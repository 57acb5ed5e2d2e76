// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Reads an activecal_identify --json_out report back and checks its
// correlation matrix: unit diagonal, symmetric, equal to
// covariance / (std std^T), positive semi-definite.
//
//   check_report_json report.json
//
// Prints "ok" and exits 0, or prints what is wrong and exits 1.

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

namespace {

bool ReadMatrix(const nlohmann::json& j, int n, Eigen::MatrixXd* m) {
  if (!j.is_array() || static_cast<int>(j.size()) != n) return false;
  m->resize(n, n);
  for (int r = 0; r < n; ++r) {
    if (!j[r].is_array() || static_cast<int>(j[r].size()) != n) return false;
    for (int c = 0; c < n; ++c) (*m)(r, c) = j[r][c].get<double>();
  }
  return true;
}

int Check(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    std::cout << path << ": cannot open\n";
    return 1;
  }
  const nlohmann::json report = nlohmann::json::parse(in);
  const nlohmann::json& params = report.at("parameters");
  const int n = static_cast<int>(params.size());
  Eigen::VectorXd sd(n);
  for (int k = 0; k < n; ++k) sd[k] = params[k].at("std").get<double>();
  Eigen::MatrixXd corr, cov;
  if (!ReadMatrix(report.at("correlation"), n, &corr)) {
    std::cout << "correlation is not " << n << " x " << n << "\n";
    return 1;
  }
  if (!ReadMatrix(report.at("covariance"), n, &cov)) {
    std::cout << "covariance is not " << n << " x " << n << "\n";
    return 1;
  }
  int bad = 0;
  for (int i = 0; i < n; ++i) {
    if (std::abs(corr(i, i) - 1) > 1e-12) {
      std::cout << "correlation(" << i << ", " << i << ") = " << corr(i, i)
                << ", expected 1\n";
      ++bad;
    }
    if (std::abs(std::sqrt(cov(i, i)) - sd[i]) > 1e-9 * sd[i]) {
      std::cout << "std[" << i << "] = " << sd[i]
                << " is not sqrt(covariance(i, i))\n";
      ++bad;
    }
    for (int j = 0; j < n; ++j) {
      if (std::abs(corr(i, j) - corr(j, i)) > 1e-12) {
        std::cout << "correlation not symmetric at (" << i << ", " << j
                  << ")\n";
        ++bad;
      }
      const double want = cov(i, j) / (sd[i] * sd[j]);
      if (std::abs(corr(i, j) - want) > 1e-9) {
        std::cout << "correlation(" << i << ", " << j << ") = " << corr(i, j)
                  << ", covariance / (std std^T) = " << want << "\n";
        ++bad;
      }
    }
    if (bad > 10) break;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(corr);
  if (eig.eigenvalues().minCoeff() < -1e-9) {
    std::cout << "correlation is not positive semi-definite: eigenvalue "
              << eig.eigenvalues().minCoeff() << "\n";
    ++bad;
  }
  if (bad) return 1;
  std::cout << "ok\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: check_report_json report.json\n";
    return 2;
  }
  try {
    return Check(argv[1]);
  } catch (const std::exception& e) {
    std::cout << argv[1] << ": " << e.what() << "\n";
    return 1;
  }
}
