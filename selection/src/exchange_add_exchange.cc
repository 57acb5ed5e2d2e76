// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/selection/exchange_add_exchange.h"

#include <glog/logging.h>

#include <Eigen/SVD>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/core/validation.h"
#include "activecal/selection/criteria.h"
#include "selection_internal.h"

namespace activecal {

bool ExchangeAddExchangeOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (num_poses <= 0) {
    msg << "num_poses must be > 0, got " << num_poses;
  } else if (initial_poses <= 0 || initial_poses > num_poses) {
    msg << "initial_poses must be in [1, num_poses = " << num_poses << "], got "
        << initial_poses;
  } else if (max_exchanges < 0) {
    msg << "max_exchanges must be >= 0, got " << max_exchanges;
  } else if (restarts <= 0) {
    msg << "restarts must be > 0, got " << restarts;
  } else if (!(min_improvement >= 0)) {
    msg << "min_improvement must be >= 0";
  }
  return FinishValidation(msg, error);
}

namespace internal {
namespace {

// The BestRemoval of both scorers: among the design's `poses` that are not
// fixed, the one of largest value_of(pose) (the first in design order on
// ties) into *pose and that value into *best_value; false when there is
// none or its value is not finite.
template <typename ValueOf>
bool BestNonFixed(const std::vector<int64_t>& poses,
                  const std::vector<char>& is_fixed, ValueOf value_of,
                  int64_t* pose, double* best_value) {
  int64_t best = -1;
  double best_v = -std::numeric_limits<double>::infinity();
  for (int64_t i : poses) {
    if (is_fixed[i]) continue;
    const double v = value_of(i);
    if (best < 0 || v > best_v) {
      best = i;
      best_v = v;
    }
  }
  if (best < 0 || !std::isfinite(best_v)) return false;
  *pose = best;
  *best_value = best_v;
  return true;
}

}  // namespace

// ---------------------------------------------------------------------------
// Determinant-update scorer.

DeterminantScorer::DeterminantScorer(const CandidatePool& pool, int num_threads,
                                     double ridge)
    : design_(pool, ridge), num_threads_(num_threads) {}

bool DeterminantScorer::BestAddition(const std::vector<char>& eligible,
                                     int64_t* pose, double* value) {
  ComputeAddGains(design_.pool(), design_.information(), num_threads_, &gains_);
  int64_t best = -1;
  for (int64_t i = 0; i < gains_.size(); ++i) {
    if (eligible[i] && !design_.Contains(i) &&
        (best < 0 || gains_[i] > gains_[best])) {
      best = i;
    }
  }
  if (best < 0) return false;
  *pose = best;
  *value = design_.log_det() + gains_[best];
  return true;
}

bool DeterminantScorer::BestRemoval(const std::vector<char>& is_fixed,
                                    int64_t* pose, double* value) {
  double loss;
  if (!BestNonFixed(
          design_.poses(), is_fixed,
          [this](int64_t i) {
            return design_.information().RemoveLoss(design_.pool().block(i));
          },
          pose, &loss)) {
    return false;
  }
  *value = design_.log_det() + loss;
  return true;
}

// ---------------------------------------------------------------------------
// Eigenvalue (SVD) scorer: log det as 2 sum log sigma_i of the stacked matrix.

namespace {
double LogDetBySvd(const Eigen::MatrixXd& X) {
  if (X.rows() < X.cols()) return -std::numeric_limits<double>::infinity();
  Eigen::BDCSVD<Eigen::MatrixXd> svd(X);
  const Eigen::VectorXd& s = svd.singularValues();
  if (s[s.size() - 1] <= s[0] * 1e-15 * X.rows()) {
    return -std::numeric_limits<double>::infinity();
  }
  return 2.0 * s.array().log().sum();
}
}  // namespace

EigenvalueScorer::EigenvalueScorer(const CandidatePool& pool, int num_threads)
    : pool_(&pool), member_(pool.size(), 0), num_threads_(num_threads) {}

void EigenvalueScorer::Add(int64_t pose) {
  poses_.push_back(pose);
  member_[pose] = 1;
  value_ = LogDetBySvd(pool_->Stack(poses_));
}

bool EigenvalueScorer::Remove(int64_t pose) {
  CHECK(member_[pose]) << "pose " << pose << " is not in the design";
  std::vector<int64_t> rest = poses_;
  rest.erase(std::find(rest.begin(), rest.end(), pose));
  const double v = LogDetBySvd(pool_->Stack(rest));
  if (!std::isfinite(v)) return false;
  poses_ = rest;
  member_[pose] = 0;
  value_ = v;
  return true;
}

bool EigenvalueScorer::BestAddition(const std::vector<char>& eligible,
                                    int64_t* pose, double* value) {
  const int t = pool_->block_rows();
  const Eigen::MatrixXd base = pool_->Stack(poses_);
  std::vector<double> values(pool_->size(),
                             -std::numeric_limits<double>::infinity());
  ParallelFor(pool_->size(), num_threads_,
              [&](int64_t begin, int64_t end, int) {
                Eigen::MatrixXd X(base.rows() + t, base.cols());
                X.topRows(base.rows()) = base;
                for (int64_t i = begin; i < end; ++i) {
                  if (!eligible[i] || member_[i]) continue;
                  X.bottomRows(t) = pool_->block(i);
                  values[i] = LogDetBySvd(X);
                }
              });
  int64_t best = -1;
  for (int64_t i = 0; i < pool_->size(); ++i) {
    if (eligible[i] && !member_[i] && (best < 0 || values[i] > values[best])) {
      best = i;
    }
  }
  if (best < 0) return false;
  *pose = best;
  *value = values[best];
  return true;
}

bool EigenvalueScorer::BestRemoval(const std::vector<char>& is_fixed,
                                   int64_t* pose, double* value) {
  return BestNonFixed(
      poses_, is_fixed,
      [this](int64_t i) {
        std::vector<int64_t> rest = poses_;
        rest.erase(std::find(rest.begin(), rest.end(), i));
        return LogDetBySvd(pool_->Stack(rest));
      },
      pose, value);
}

// ---------------------------------------------------------------------------

double RegularisingRidge(const CandidatePool& pool) {
  // tr(sum_i X_i^T X_i) / (pool size * p): the mean diagonal entry of one
  // pose's information.
  const double mean_diagonal = pool.stacked().squaredNorm() /
                               pool.num_parameters() /
                               std::max<int64_t>(1, pool.size());
  return 1e-9 * mean_diagonal;
}

int CompleteSingularDesign(const CandidatePool& pool,
                           const std::vector<char>& eligible, int num_threads,
                           std::vector<int64_t>* poses) {
  DeterminantScorer design(pool, num_threads, RegularisingRidge(pool));
  for (int64_t i : *poses) design.Add(i);
  InformationMatrix plain(pool.num_parameters());
  for (int64_t i : *poses) plain.Add(pool.block(i));
  int added = 0;
  while (!plain.positive_definite()) {
    int64_t best;
    double value;
    // None left: the pool itself is rank deficient.
    if (!design.BestAddition(eligible, &best, &value)) return -1;
    design.Add(best);
    plain.Add(pool.block(best));
    poses->push_back(best);
    ++added;
  }
  return added;
}

bool ExchangeStep(Scorer* scorer, const std::vector<char>& eligible,
                  const std::vector<char>& is_fixed, int max_exchanges,
                  double min_improvement, std::vector<SelectionStep>* history) {
  for (int k = 0; k < max_exchanges; ++k) {
    const double current = scorer->Value();
    int64_t out, in;
    double after_removal, after_swap;
    if (!scorer->BestRemoval(is_fixed, &out, &after_removal)) return false;
    if (!scorer->Remove(out)) return false;
    if (!scorer->BestAddition(eligible, &in, &after_swap) || in == out ||
        !(after_swap >
          current + ImprovementThreshold(current, min_improvement))) {
      scorer->Add(out);  // undo
      return false;
    }
    scorer->Add(in);
    history->push_back({SelectionStep::kExchange, in, out, scorer->Value()});
  }
  return max_exchanges > 0;
}

}  // namespace internal

bool ExchangeAddExchange(const CandidatePool& pool,
                         const DesignConstraints& constraints,
                         const ExchangeAddExchangeOptions& options,
                         SelectionSummary* summary) {
  internal::SelectionStart start;
  const char* algorithm =
      options.criterion == SelectionCriterion::kDeterminantUpdate
          ? "exchange-add-exchange (determinant update)"
          : "exchange-add-exchange (eigenvalue OI)";
  if (!internal::PrepareSelection(pool, constraints, options, algorithm,
                                  summary, &start)) {
    return false;
  }
  const int num_fixed = static_cast<int>(constraints.fixed.size());
  if (options.initial_poses < num_fixed) {
    summary->message = "initial_poses (" +
                       std::to_string(options.initial_poses) +
                       ") is smaller than the number of fixed poses (" +
                       std::to_string(num_fixed) + ")";
    return false;
  }

  // A singular start is completed greedily and trimmed back to
  // initial_poses (or as close as non-singularity allows).
  return internal::RunRestartsFromInitialDesigns(
      pool, constraints, options, start, options.initial_poses,
      [&](const internal::WorkingSet& work, int threads, std::string* note,
          internal::RestartResult* result) {
        const std::vector<int64_t>& initial = result->design;
        if (static_cast<int>(initial.size()) > options.num_poses) {
          *note = "no non-singular design of " +
                  std::to_string(options.num_poses) +
                  " poses was found from a singular start (the smallest "
                  "has " +
                  std::to_string(initial.size()) + " poses)";
          return false;
        }
        std::unique_ptr<internal::Scorer> scorer;
        if (options.criterion == SelectionCriterion::kDeterminantUpdate) {
          scorer = std::make_unique<internal::DeterminantScorer>(pool, threads);
        } else {
          scorer = std::make_unique<internal::EigenvalueScorer>(pool, threads);
        }
        for (int64_t i : initial) scorer->Add(i);
        result->history.push_back(
            {SelectionStep::kInitial, -1, -1, scorer->Value()});
        result->hit_bound |= internal::ExchangeStep(
            scorer.get(), work.eligible, work.is_fixed, options.max_exchanges,
            options.min_improvement, &result->history);
        while (scorer->size() < options.num_poses &&
               scorer->Value() < options.target_log_det) {
          int64_t in;
          double after;
          if (!scorer->BestAddition(work.eligible, &in, &after) ||
              !(after > scorer->Value() +
                            internal::ImprovementThreshold(
                                scorer->Value(), options.min_improvement))) {
            break;
          }
          scorer->Add(in);
          result->history.push_back(
              {SelectionStep::kAdd, in, -1, scorer->Value()});
        }
        result->hit_bound |= internal::ExchangeStep(
            scorer.get(), work.eligible, work.is_fixed, options.max_exchanges,
            options.min_improvement, &result->history);
        result->design = scorer->poses();
        return true;
      },
      summary);
}

}  // namespace activecal
