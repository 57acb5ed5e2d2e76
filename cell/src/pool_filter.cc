// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/cell/pool_filter.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/io/csv_files.h"

namespace activecal {
namespace {

// A CSV field, quoted when it holds a separator or a quote.
std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

}  // namespace

std::string PoolFilterSummary::CountsText(const CellChecker& checker) const {
  return RejectionCountsText(checker, rejected, rejected_by_obstacle);
}

std::string PoolFilterSummary::BriefReport(const CellChecker& checker) const {
  char head[160];
  std::snprintf(head, sizeof(head),
                "cell: %lld of %lld poses feasible (%.3g s)",
                static_cast<long long>(num_feasible()),
                static_cast<long long>(num_poses), seconds);
  return std::string(head) + "; rejected: " + CountsText(checker) + "\n";
}

Eigen::MatrixXd PoolFilterSummary::FeasibleJoints(
    const Eigen::MatrixXd& joints) const {
  Eigen::MatrixXd out(feasible.size(), joints.cols());
  for (size_t k = 0; k < feasible.size(); ++k) {
    out.row(k) = joints.row(feasible[k]);
  }
  return out;
}

bool FilterPool(const CellChecker& checker, const Eigen::MatrixXd& joints,
                const PoolFilterOptions& options, PoolFilterSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  *summary = PoolFilterSummary();
  PoolFilterSummary& s = *summary;
  if (joints.cols() != checker.model().num_joints()) {
    s.termination_type = TerminationType::kUserFailure;
    s.message = "the pool has " + std::to_string(joints.cols()) +
                " joint columns, the robot " +
                std::to_string(checker.model().num_joints()) + " joints";
    return false;
  }
  const int64_t n = joints.rows();
  s.num_poses = n;
  s.verdicts.resize(n);
  // Row-major copies of a chunk at a time keep each pose's joints together.
  const int threads = ResolveNumThreads(options.num_threads);
  std::atomic<int64_t> done{0};
  ParallelFor(n, threads, [&](int64_t begin, int64_t end, int) {
    auto workspace = checker.NewWorkspace();
    Eigen::VectorXd q(joints.cols());
    int64_t since = 0;
    for (int64_t i = begin; i < end; ++i) {
      q = joints.row(i).transpose();
      s.verdicts[i] = checker.Check(q.data(), workspace.get());
      if (++since == 4096) {
        const int64_t total = done.fetch_add(since) + since;
        since = 0;
        if (options.progress) options.progress(total, n);
      }
    }
    const int64_t total = done.fetch_add(since) + since;
    if (options.progress) options.progress(total, n);
  });
  s.rejected_by_obstacle.assign(checker.cell().obstacles.size(), 0);
  Eigen::VectorXd q(joints.cols());
  for (int64_t i = 0; i < n; ++i) {
    const PoseVerdict& v = s.verdicts[i];
    if (v.reason == RejectionReason::kSelfCollision ||
        v.reason == RejectionReason::kObstacle) {
      q = joints.row(i).transpose();  // the pair's example pose
    }
    s.counts.Add(v, q.data(), static_cast<int>(q.size()));
    if (v.feasible()) {
      s.feasible.push_back(i);
      s.targets_seen.push_back(v.targets_seen);
      continue;
    }
    ++s.rejected[static_cast<int>(v.reason)];
    if (v.reason == RejectionReason::kObstacle && v.a >= 0) {
      ++s.rejected_by_obstacle[v.a];
    }
  }
  s.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  s.termination_type = TerminationType::kConvergence;
  return true;
}

std::string RejectedCsvText(const CellChecker& checker,
                            const Eigen::MatrixXd& joints,
                            const std::vector<int64_t>& labels,
                            const PoolFilterSummary& summary) {
  PoseList list;
  std::vector<int64_t> rows;
  for (int64_t i = 0; i < static_cast<int64_t>(summary.verdicts.size()); ++i) {
    if (!summary.verdicts[i].feasible()) rows.push_back(i);
  }
  list.joints.resize(rows.size(), joints.cols());
  for (size_t k = 0; k < rows.size(); ++k) {
    list.joints.row(k) = joints.row(rows[k]);
    list.pose_indices.push_back(labels.empty() ? rows[k] : labels[rows[k]]);
  }
  const std::string poses = PosesCsvText(checker.model(), list);
  std::istringstream in(poses);
  std::string line, out;
  bool header = true;
  size_t k = 0;
  while (std::getline(in, line)) {
    if (header) {
      out += line + ",reason,obstacle,detail\n";
      header = false;
      continue;
    }
    const PoseVerdict& v = summary.verdicts[rows[k++]];
    const std::string obstacle = v.reason == RejectionReason::kObstacle
                                     ? checker.cell().obstacles[v.a].name
                                     : std::string();
    out += line + "," + RejectionReasonToString(v.reason) + "," +
           CsvField(obstacle) + "," + CsvField(checker.Detail(v)) + "\n";
  }
  return out;
}

}  // namespace activecal
