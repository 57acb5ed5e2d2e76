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
#include "activecal/core/random.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/design.h"
#include "sub_pool.h"

namespace activecal {
namespace internal {

// The value of a criterion that cannot be evaluated (a singular matrix).
constexpr double kInf = std::numeric_limits<double>::infinity();

// The Remove of Design and TaskDesign: CHECK-fails for a pose not in the
// design; false (nothing changed) when `info` cannot remove its block; else
// the pose leaves info, member and poses.
bool RemoveDesignPose(const CandidatePool& pool, int64_t pose,
                      InformationMatrix* info, std::vector<char>* member,
                      std::vector<int64_t>* poses);

// Calls fn(begin, count) for the chunks of 512 poses (the last one
// shorter) covering poses [0, n), the chunks split over num_threads threads
// by ParallelFor: the sweeps over the pool take one product per chunk.
void ForEachPoseChunk(int64_t n, int num_threads,
                      const std::function<void(int64_t, int64_t)>& fn);

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

// log det of a design from the pool's exact blocks (CandidatePool::
// ExactBlock: the exact source if any, else the stored blocks), in double.
double LogDetOfExactBlocks(const CandidatePool& pool,
                           const std::vector<int64_t>& design);

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

// A starting design of num_poses poses on work.pool: the fixed poses, then
// (if given) poses of an approximate design (its heaviest, or if
// `randomized` a draw proportional to the weights), then random eligible
// poses drawn with `seed`. A singular start is completed greedily and
// trimmed back. Empty if the pool cannot give a non-singular design.
std::vector<int64_t> InitialDesign(const WorkingSet& work, int num_poses,
                                   uint64_t seed,
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

// What a selection starts from once PrepareSelection has checked it: when
// it started (the summary's seconds) and the eligible and the fixed poses
// of the pool (1 each).
struct SelectionStart {
  std::chrono::steady_clock::time_point time = std::chrono::steady_clock::now();
  std::vector<char> eligible;
  std::vector<char> is_fixed;
};

// PositiveCounts of the options' num_poses and restarts, the checks the
// restarted designs' options start with.
template <typename Options>
bool PositivePosesAndRestarts(const Options& options, std::ostream* msg) {
  return PositiveCounts(
      {{"num_poses", options.num_poses}, {"restarts", options.restarts}}, msg);
}

// Resets the summary, checks the options and the constraints, and marks the
// eligible and the fixed poses in *start.
template <typename Options>
bool PrepareSelection(const CandidatePool& pool,
                      const DesignConstraints& constraints,
                      const Options& options, const char* algorithm,
                      SelectionSummary* summary, SelectionStart* start,
                      int64_t prior_equations = 0) {
  *summary = SelectionSummary();
  summary->algorithm = algorithm;
  summary->num_parameters = pool.num_parameters();
  summary->pool_size = pool.size();
  std::string error;
  if (!options.IsValid(&error) ||
      !PrepareCandidates(pool, options.num_poses, constraints, &start->eligible,
                         &error, prior_equations)) {
    summary->message = error;
    return false;
  }
  start->is_fixed.assign(pool.size(), 0);
  for (int64_t f : constraints.fixed) start->is_fixed[f] = 1;
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

// The restarts of DETMAX and exchange-add-exchange, on the whole pool
// (options.restarts of them on options.num_threads, reporting to
// options.progress, as BestOfRestarts runs them). Restart r starts from
// InitialDesign(work, start_poses, stream r of options.seed) (no design,
// with its note, when that fails); then run(work, inner_threads, &note,
// &result) improves result.design (the start on entry), leaving its steps
// in result.history and setting result.hit_bound, or returns false for a
// restart that gives no design; the restart ends on result.design
// (FinishRestart). The summary is filled from the best restart, with its
// note (FinishSummary). Returns summary->IsSolutionUsable().
template <typename Options>
bool RunRestartsFromInitialDesigns(
    const CandidatePool& pool, const DesignConstraints& constraints,
    const Options& options, const SelectionStart& start, int start_poses,
    const std::function<bool(const WorkingSet&, int, std::string*,
                             RestartResult*)>& run,
    SelectionSummary* summary) {
  const WorkingSet work(pool, nullptr, constraints, start.eligible,
                        start.is_fixed);
  std::vector<std::string> notes(options.restarts);
  const RestartResult best = BestOfRestarts(
      options.restarts, options.num_threads,
      [&](int r, int threads) {
        RestartResult result;
        result.design = InitialDesign(work, start_poses,
                                      Random::StreamSeed(options.seed, r),
                                      nullptr, false, threads, &notes[r]);
        if (result.design.empty() || !run(work, threads, &notes[r], &result)) {
          return RestartResult();
        }
        FinishRestart(pool, std::move(result.design), &result);
        return result;
      },
      options.progress);
  FinishSummary(best, options.restarts, start.time, NoteOf(notes, best.restart),
                summary);
  return summary->IsSolutionUsable();
}

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
