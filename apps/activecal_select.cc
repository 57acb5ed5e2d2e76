// activecal_select: choose calibration poses for the paper's PUMA 560 from
// a joint lattice by a D-optimal design algorithm.

#include <cstdio>
#include <iostream>

#include <gflags/gflags.h>

#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "activecal/selection/random_designs.h"
#include "app_common.h"

DEFINE_int32(levels, 5,
             "Lattice values per joint, both range ends included (>= 2). "
             "The pool has levels^6 poses.");
DEFINE_string(algorithm, "eae",
              "eae: the paper's exchange-add-exchange; random: best of "
              "--random_designs random designs.");
DEFINE_string(criterion, "det",
              "For eae: det scores candidates by the determinant update "
              "formulas (fast); svd by the eigenvalue OI of the stacked "
              "design matrix (slow; same poses).");
DEFINE_int32(num_poses, 30, "Poses in the design.");
DEFINE_int32(initial_poses, 12, "eae: random poses in the initial design.");
DEFINE_int32(random_designs, 5000, "random: number of designs drawn.");
DEFINE_int32(restarts, 1, "eae: independent random restarts; the best is "
                          "kept.");
DEFINE_uint64(seed, 1, "Seed of every random choice.");
DEFINE_int32(threads, 0, "Threads (0: all). Results do not depend on it.");
DEFINE_string(json_out, "", "If set, write the selected design here.");

namespace activecal {
namespace {

int Main() {
  const RobotModel model = Puma560PaperModel();
  const JointLattice lattice = app::MakeLatticeOrDie(model, FLAGS_levels);
  double jacobian_seconds = 0;
  const CandidatePool pool = app::MakeLatticePoolOrDie(
      model, model.nominal, lattice, FLAGS_threads, &jacobian_seconds);

  SelectionSummary summary;
  bool ok = false;
  if (FLAGS_algorithm == "eae") {
    ExchangeAddExchangeOptions options;
    options.num_poses = FLAGS_num_poses;
    options.initial_poses = FLAGS_initial_poses;
    options.restarts = FLAGS_restarts;
    options.seed = FLAGS_seed;
    options.num_threads = FLAGS_threads;
    if (FLAGS_criterion == "det") {
      options.criterion = SelectionCriterion::kDeterminantUpdate;
    } else if (FLAGS_criterion == "svd") {
      options.criterion = SelectionCriterion::kEigenvalueOi;
    } else {
      app::Fail("--criterion must be det or svd, got '" + FLAGS_criterion +
                "'");
    }
    ok = ExchangeAddExchange(pool, {}, options, &summary);
  } else if (FLAGS_algorithm == "random") {
    RandomDesignOptions options;
    options.num_poses = FLAGS_num_poses;
    options.num_designs = FLAGS_random_designs;
    options.seed = FLAGS_seed;
    options.num_threads = FLAGS_threads;
    ok = SelectRandomDesigns(pool, {}, options, &summary);
  } else {
    app::Fail("--algorithm must be eae or random, got '" + FLAGS_algorithm +
              "'");
  }
  if (!ok) app::Fail(summary.message);

  std::printf("%s", summary.BriefReport().c_str());
  std::printf("  Jacobians of %lld poses: %.3f s\n",
              static_cast<long long>(pool.size()), jacobian_seconds);
  std::printf("  %-6s %-8s %s\n", "#", "index", "levels (joint 1..6)");
  for (size_t k = 0; k < summary.design.size(); ++k) {
    std::printf("  %-6zu %-8lld", k,
                static_cast<long long>(summary.design[k]));
    for (int l : lattice.Levels(summary.design[k])) std::printf(" %d", l);
    std::printf("\n");
  }
  if (!FLAGS_json_out.empty()) {
    nlohmann::json j = app::SelectionJson(summary, lattice);
    j["seed"] = FLAGS_seed;
    j["levels"] = FLAGS_levels;
    j["jacobian_seconds"] = jacobian_seconds;
    app::WriteJsonOrDie(FLAGS_json_out, j);
  }
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  activecal::app::Init(
      &argc, &argv,
      "Selects calibration poses for the Sun & Hollerbach PUMA 560 from a "
      "lattice of joint values, maximising det(X^T X) of the position "
      "Jacobian at the nominal parameters.\n  activecal_select "
      "--algorithm=eae --seed=1 --json_out=design.json");
  return activecal::Main();
}
