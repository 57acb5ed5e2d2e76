// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Internal pieces shared by the selection algorithms. Not installed.

#ifndef ACTIVECAL_SELECTION_SRC_SELECTION_INTERNAL_H_
#define ACTIVECAL_SELECTION_SRC_SELECTION_INTERNAL_H_

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <limits>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "activecal/core/candidate_pool.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/design.h"

namespace activecal {
namespace internal {

// Calls fn(i, X_i V X_i^T) for every pool pose, in parallel chunks (fn must
// only write per-pose results), reading the stored or the exact blocks.
void ForEachQuadraticForm(
    const CandidatePool& pool, const Eigen::MatrixXd& V, int num_threads,
    const std::function<void(int64_t, const Eigen::MatrixXd&)>& fn,
    PoolReading reading = PoolReading::kStored);

// A design together with a way of scoring single-pose changes to it.
// Values are natural log det X^T X (or, for the SVD scorer, the same
// quantity computed from singular values).
class Scorer {
 public:
  virtual ~Scorer() = default;
  virtual double Value() const = 0;
  virtual int size() const = 0;
  virtual const std::vector<int64_t>& poses() const = 0;
  virtual void Add(int64_t pose) = 0;
  virtual bool Remove(int64_t pose) = 0;
  // The eligible pose not in the design whose addition gives the highest
  // value; ties go to the lowest index.
  virtual bool BestAddition(const std::vector<char>& eligible, int64_t* pose,
                            double* value) = 0;
  // The design pose (not fixed) whose removal leaves the highest value.
  virtual bool BestRemoval(const std::vector<char>& is_fixed, int64_t* pose,
                           double* value) = 0;
};

class DeterminantScorer : public Scorer {
 public:
  // ridge > 0: scores on M + ridge I (a start that is still singular).
  DeterminantScorer(const CandidatePool& pool, int num_threads,
                    double ridge = 0.0);
  double Value() const override { return design_.log_det(); }
  int size() const override { return design_.size(); }
  const std::vector<int64_t>& poses() const override { return design_.poses(); }
  void Add(int64_t pose) override { design_.Add(pose); }
  bool Remove(int64_t pose) override { return design_.Remove(pose); }
  bool BestAddition(const std::vector<char>& eligible, int64_t* pose,
                    double* value) override;
  bool BestRemoval(const std::vector<char>& is_fixed, int64_t* pose,
                   double* value) override;

 private:
  Design design_;
  int num_threads_;
  Eigen::VectorXd gains_;
};

class EigenvalueScorer : public Scorer {
 public:
  EigenvalueScorer(const CandidatePool& pool, int num_threads);
  double Value() const override { return value_; }
  int size() const override { return static_cast<int>(poses_.size()); }
  const std::vector<int64_t>& poses() const override { return poses_; }
  void Add(int64_t pose) override;
  bool Remove(int64_t pose) override;
  bool BestAddition(const std::vector<char>& eligible, int64_t* pose,
                    double* value) override;
  bool BestRemoval(const std::vector<char>& is_fixed, int64_t* pose,
                   double* value) override;

 private:
  const CandidatePool* pool_;
  std::vector<int64_t> poses_;
  std::vector<char> member_;
  int num_threads_;
  double value_ = -std::numeric_limits<double>::infinity();
};

// The ridge eps used while a design is singular: 1e-9 times the mean
// diagonal entry of one pool pose's X_i^T X_i.
double RegularisingRidge(const CandidatePool& pool);

// Completes a singular design greedily on M + eps I until M is positive
// definite. Returns the number of poses added, or -1 if the eligible pool
// cannot make M positive definite.
int CompleteSingularDesign(const CandidatePool& pool,
                           const std::vector<char>& eligible, int num_threads,
                           std::vector<int64_t>* poses);

// The paper's exchange step: swaps while one raises log det. Returns
// whether max_exchanges stopped it (rather than no swap helping).
bool ExchangeStep(Scorer* scorer, const std::vector<char>& eligible,
                  const std::vector<char>& is_fixed, int max_exchanges,
                  double min_improvement, std::vector<SelectionStep>* history);

// The least rise of log det a step must make to be accepted: a relative
// threshold, rel * max(1, |log_det|), so that rounding in a log det that
// is huge or tiny cannot pass for progress.
inline double ImprovementThreshold(double log_det, double rel) {
  return rel * std::max(1.0, std::abs(log_det));
}

// One restart's outcome.
struct RestartResult {
  bool ok = false;
  // An iteration bound stopped it (the design is still valid).
  bool hit_bound = false;
  int restart = 0;
  std::vector<int64_t> design;
  std::vector<SelectionStep> history;
  double log_det = -std::numeric_limits<double>::infinity();
};

// Ends a restart on `design`: the design, its log det (from scratch) and
// ok if that is finite.
inline void FinishRestart(const CandidatePool& pool,
                          std::vector<int64_t> design, RestartResult* result) {
  result->design = std::move(design);
  result->log_det = LogDetFromScratch(pool, result->design);
  result->ok = std::isfinite(result->log_det);
}

// Runs restarts 0..restarts-1 (in parallel when there are at least as many
// restarts as threads, otherwise one after the other with all threads each)
// and returns the best by log det, the lowest restart on ties.
RestartResult BestOfRestarts(
    int restarts, int num_threads,
    const std::function<RestartResult(int restart, int inner_threads)>& run,
    const ProgressCallback& progress = ProgressCallback());

// A starting design of num_poses poses: the fixed poses, then (if given)
// poses of an approximate design (its heaviest, or if `randomized` a draw
// proportional to the weights), then random eligible poses drawn with
// `seed`. A singular start is completed greedily and trimmed back.
// Empty if the pool cannot give a non-singular design.
std::vector<int64_t> InitialDesign(const CandidatePool& pool,
                                   const DesignConstraints& constraints,
                                   const std::vector<char>& eligible,
                                   int num_poses, uint64_t seed,
                                   const ApproximateDesignSummary* approximate,
                                   bool randomized, int num_threads,
                                   std::string* note);

// The checks the designs' options start with: for the first of `counts`
// ({name, value}) that is not > 0, "<name> must be > 0, got <value>" into
// *msg and false; true if all are.
inline bool PositiveCounts(
    std::initializer_list<std::pair<const char*, int>> counts,
    std::ostream* msg) {
  for (const auto& [name, value] : counts) {
    if (value <= 0) {
      *msg << name << " must be > 0, got " << value;
      return false;
    }
  }
  return true;
}

// Resets the summary, checks the options and the constraints, and marks the
// eligible and the fixed poses.
template <typename Options>
bool PrepareSelection(const CandidatePool& pool,
                      const DesignConstraints& constraints,
                      const Options& options, const char* algorithm,
                      SelectionSummary* summary, std::vector<char>* eligible,
                      std::vector<char>* is_fixed,
                      int64_t prior_equations = 0) {
  *summary = SelectionSummary();
  summary->algorithm = algorithm;
  summary->num_parameters = pool.num_parameters();
  summary->pool_size = pool.size();
  std::string error;
  if (!options.IsValid(&error) ||
      !PrepareCandidates(pool, options.num_poses, constraints, eligible, &error,
                         prior_equations)) {
    summary->message = error;
    return false;
  }
  is_fixed->assign(pool.size(), 0);
  for (int64_t f : constraints.fixed) (*is_fixed)[f] = 1;
  return true;
}

// The note a restart left, if any.
inline std::string NoteOf(const std::vector<std::string>& notes, int restart) {
  return restart < static_cast<int>(notes.size()) ? notes[restart] : "";
}

// Fills the summary from the best restart: the design, its history, the
// termination type (FAILURE if no restart gave a design, NO_CONVERGENCE if
// an iteration bound stopped it) and the message, with `note` appended.
void FinishSummary(const RestartResult& best, int restarts,
                   std::chrono::steady_clock::time_point start,
                   const std::string& note, SelectionSummary* summary);

// Tries DETMAX excursions of size min_size..max_excursion on `poses` (add k
// best then remove k, or remove k then add k). Returns true and updates
// poses when one raises log det (recomputed from scratch) by more than
// ImprovementThreshold(log det, min_improvement).
bool TryExcursion(const CandidatePool& pool, const std::vector<char>& eligible,
                  const std::vector<char>& is_fixed, int min_size,
                  int max_excursion, double min_improvement, int threads,
                  std::vector<int64_t>* poses, SelectionStep* step);

}  // namespace internal
}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_SRC_SELECTION_INTERNAL_H_
