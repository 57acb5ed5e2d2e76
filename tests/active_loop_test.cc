// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The active loop: the residual check, poses the measurer cannot measure
// (excluded, never asked again, the design repaired), the pool filter, the
// measured joints identified from, resuming from any round, and the
// session directory that loses nothing.

#include "activecal/calibration/active_loop.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>

#include "activecal/calibration/active_session.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/io/csv_files.h"
#include "test_util.h"

namespace activecal {
namespace {

// A selector without selection: the fixed poses, then eligible poses from
// a round-dependent start with a stride of 7 (wrapping), so that batches
// are spread over the lattice and deterministic.
bool StridePoses(const CandidatePool& pool, const Eigen::MatrixXd&,
                 const RowMatrixXd&, const BatchRequest& request,
                 std::vector<int64_t>* batch, std::string*) {
  *batch = request.fixed;
  std::set<int64_t> in(batch->begin(), batch->end());
  const int64_t n = pool.size();
  for (int64_t k = 0;
       static_cast<int>(batch->size()) < request.num_poses && k < 7 * n; ++k) {
    const int64_t i = (request.round * 3 + 7 * k) % n;
    if (in.count(i) || (request.excluded && request.excluded(i))) continue;
    in.insert(i);
    batch->push_back(i);
  }
  return true;
}

// Counts what the loop asks of the measurer it wraps.
class CountingMeasurer : public Measurer {
 public:
  explicit CountingMeasurer(Measurer* inner) : inner_(inner) {}
  bool Measure(const MeasureBatch& batch, int k, PoseAnswer* answer,
               std::string* error) override {
    ++asked[batch.poses[k]];
    if (batch.attempt > 0) ++repairs;
    if (fail_after >= 0 && total >= fail_after) {
      *error = "the cell stopped";
      return false;
    }
    ++total;
    return inner_->Measure(batch, k, answer, error);
  }
  std::map<int64_t, int> asked;
  int repairs = 0;
  int total = 0;
  int fail_after = -1;

 private:
  Measurer* inner_;
};

struct Puma {
  RobotModel model = Puma560PaperModel();
  Eigen::VectorXd truth = Puma560TrueParameters();
  Eigen::MatrixXd joints = testing::PumaLatticeJoints(3);
};

ActiveLoopOptions SmallLoop(const Puma& p) {
  ActiveLoopOptions options;
  options.sigma_m = 1e-4;
  options.target_rms_m = 1e-9;  // never met: the rounds run out
  options.first_batch = 30;
  options.batch_size = 6;
  options.max_rounds = 3;
  options.true_parameters = p.truth;
  return options;
}

void ExpectSameSummary(const ActiveLoopSummary& a, const ActiveLoopSummary& b) {
  EXPECT_EQ(a.termination_type, b.termination_type);
  EXPECT_EQ(a.message, b.message);
  EXPECT_EQ(a.measured, b.measured);
  ASSERT_EQ(a.estimate.size(), b.estimate.size());
  for (Eigen::Index i = 0; i < a.estimate.size(); ++i) {
    EXPECT_EQ(a.estimate[i], b.estimate[i]) << "parameter " << i;
  }
  ASSERT_EQ(a.rounds.size(), b.rounds.size());
  for (size_t r = 0; r < a.rounds.size(); ++r) {
    EXPECT_EQ(a.rounds[r].batch, b.rounds[r].batch);
    EXPECT_EQ(a.rounds[r].excluded, b.rounds[r].excluded);
    EXPECT_EQ(a.rounds[r].predicted_task_rms_m,
              b.rounds[r].predicted_task_rms_m);
    EXPECT_EQ(a.rounds[r].true_task_rms_m, b.rounds[r].true_task_rms_m);
    EXPECT_EQ(a.rounds[r].residual_sigma_m, b.rounds[r].residual_sigma_m);
  }
  ASSERT_EQ(a.excluded.size(), b.excluded.size());
  for (size_t k = 0; k < a.excluded.size(); ++k) {
    EXPECT_EQ(a.excluded[k].pose, b.excluded[k].pose);
  }
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string TempDir(const std::string& name) {
  std::string tmpl = ::testing::TempDir() + "/activecal_" + name + "_XXXXXX";
  EXPECT_NE(mkdtemp(tmpl.data()), nullptr);
  return tmpl;
}

// The loop cannot know the truth, but it can see that the identified model
// does not explain the measurements. A truth carrying an error the model
// lacks (a parameter held fixed, 2 mm off) leaves residuals well above the
// noise: the round is flagged and a predicted target is not reported as
// met. The same loop on a truth the model can express converges with
// residuals at the noise level.
TEST(ActiveLoopTest, ResidualsAboveTheNoiseAreNotConvergence) {
  RobotModel model = Puma560PaperModel();
  const Eigen::VectorXd truth = Puma560TrueParameters();
  model.nominal = truth;
  JointLattice lattice;
  std::string error;
  ASSERT_TRUE(JointLattice::Create(model, 3, &lattice, &error)) << error;
  const Eigen::MatrixXd joints = lattice.AllJointValues();
  ActiveLoopOptions options;
  options.sigma_m = 1e-4;
  options.target_rms_m = 1.0;  // met by the first round's prediction
  options.first_batch = 40;
  options.max_rounds = 1;
  BatchSelector first_poses = [](const CandidatePool&, const Eigen::MatrixXd&,
                                 const RowMatrixXd&,
                                 const BatchRequest& request,
                                 std::vector<int64_t>* batch, std::string*) {
    batch->clear();
    for (int64_t i = 0; static_cast<int>(batch->size()) < request.num_poses;
         i += 7) {
      batch->push_back(i + static_cast<int64_t>(request.measured.size()));
    }
    return true;
  };
  ActiveLoopSummary fits;
  ASSERT_TRUE(
      RunActiveLoop(model, truth, joints, joints, options, first_poses, &fits))
      << fits.message;
  EXPECT_EQ(fits.termination_type, TerminationType::kConvergence)
      << fits.message;
  ASSERT_EQ(fits.rounds.size(), 1u);
  EXPECT_FALSE(fits.rounds[0].residuals_exceed_noise);
  EXPECT_GT(fits.rounds[0].residual_sigma_m, 0.5 * options.sigma_m);
  EXPECT_LT(fits.rounds[0].residual_sigma_m, 1.5 * options.sigma_m);

  // An error the model lacks: link 2's length held at a value 2 mm off.
  const int fixed = 6 * 2 + kA;
  ASSERT_TRUE(model.IsFree(fixed));
  model.SetFree(fixed, false);
  Eigen::VectorXd unmodelled = truth;
  unmodelled[fixed] += 2e-3;
  ActiveLoopSummary lacks;
  ASSERT_TRUE(RunActiveLoop(model, unmodelled, joints, joints, options,
                            first_poses, &lacks))
      << lacks.message;
  ASSERT_EQ(lacks.rounds.size(), 1u);
  EXPECT_LE(lacks.rounds[0].predicted_task_rms_m, options.target_rms_m);
  EXPECT_TRUE(lacks.rounds[0].residuals_exceed_noise);
  EXPECT_GT(lacks.rounds[0].residual_sigma_m, 2 * options.sigma_m);
  EXPECT_EQ(lacks.termination_type, TerminationType::kNoConvergence);
  EXPECT_NE(lacks.message.find("does not fit the measurements"),
            std::string::npos)
      << lacks.message;
  // The check can be switched off.
  options.residual_ratio_limit = 0;
  ASSERT_TRUE(RunActiveLoop(model, unmodelled, joints, joints, options,
                            first_poses, &lacks));
  EXPECT_EQ(lacks.termination_type, TerminationType::kConvergence);
}

// A pose the cell cannot measure is asked once, excluded for good, and the
// round's batch is repaired from the pool to its full size.
TEST(ActiveLoopTest, UnmeasurablePosesAreExcludedOnceAndTheBatchRepaired) {
  const Puma p;
  const ActiveLoopOptions options = SmallLoop(p);
  SimulatedMeasurer robot(p.model, p.truth, options.sigma_m, options.seed);
  auto hidden = [](int64_t i) { return i % 4 == 1; };
  robot.set_not_visible(hidden);
  CountingMeasurer counting(&robot);
  ActiveLoopSummary summary;
  ASSERT_TRUE(RunActiveLoop(p.model, p.joints, p.joints, options, StridePoses,
                            &counting, nullptr, &summary))
      << summary.message;
  EXPECT_EQ(summary.termination_type, TerminationType::kNoConvergence);
  ASSERT_EQ(summary.rounds.size(), 3u);
  for (const auto& [pose, times] : counting.asked) {
    EXPECT_EQ(times, 1) << "pose " << pose << " asked " << times << " times";
  }
  // Every batch reached its size with visible poses only.
  const size_t sizes[] = {30, 6, 6};
  size_t excluded = 0;
  for (size_t r = 0; r < 3; ++r) {
    EXPECT_EQ(summary.rounds[r].batch.size(), sizes[r]) << "round " << r;
    for (int64_t i : summary.rounds[r].batch) EXPECT_FALSE(hidden(i)) << i;
    for (int64_t i : summary.rounds[r].excluded) EXPECT_TRUE(hidden(i)) << i;
    excluded += summary.rounds[r].excluded.size();
  }
  EXPECT_GT(excluded, 0u);
  EXPECT_GT(counting.repairs, 0);
  ASSERT_EQ(summary.excluded.size(), excluded);
  for (const ExcludedPose& e : summary.excluded) {
    EXPECT_TRUE(hidden(e.pose));
    EXPECT_EQ(e.status, "not_visible");
    EXPECT_EQ(
        std::count(summary.measured.begin(), summary.measured.end(), e.pose),
        0);
  }
  EXPECT_EQ(summary.rounds.back().num_poses, 42);
  EXPECT_EQ(counting.total, static_cast<int>(42 + excluded));
}

// Every pose of the pool hidden: the loop ends, saying so, after asking
// each pose once.
TEST(ActiveLoopTest, APoolWithNothingVisibleEndsTheLoop) {
  const Puma p;
  ActiveLoopOptions options = SmallLoop(p);
  SimulatedMeasurer robot(p.model, p.truth, options.sigma_m, options.seed);
  robot.set_not_visible([](int64_t) { return true; });
  CountingMeasurer counting(&robot);
  ActiveLoopSummary summary;
  EXPECT_TRUE(RunActiveLoop(p.model, p.joints, p.joints, options, StridePoses,
                            &counting, nullptr, &summary));
  EXPECT_EQ(summary.termination_type, TerminationType::kNoConvergence);
  EXPECT_EQ(summary.message, "every pool pose is measured or excluded");
  EXPECT_EQ(counting.asked.size(), static_cast<size_t>(p.joints.rows()));
  EXPECT_TRUE(summary.rounds.empty());
}

// The pool filter (the cell's reachability test, later) bars poses from
// every batch and repair.
TEST(ActiveLoopTest, ThePoolFilterBarsPoses) {
  const Puma p;
  ActiveLoopOptions options = SmallLoop(p);
  options.pool_filter = [](int64_t i) { return i % 2 == 1; };
  SimulatedMeasurer robot(p.model, p.truth, options.sigma_m, options.seed);
  robot.set_not_visible([](int64_t i) { return i % 10 == 3; });
  CountingMeasurer counting(&robot);
  ActiveLoopSummary summary;
  ASSERT_TRUE(RunActiveLoop(p.model, p.joints, p.joints, options, StridePoses,
                            &counting, nullptr, &summary))
      << summary.message;
  EXPECT_FALSE(counting.asked.empty());
  for (const auto& kv : counting.asked) EXPECT_EQ(kv.first % 2, 1) << kv.first;
}

// The joints the cell reads are what is identified from: a robot that stops
// 0.02 rad off the commanded pose, reading its encoders exactly and
// measured without noise, is identified exactly; the same points paired
// with the commanded joints are not.
class ServoErrorMeasurer : public Measurer {
 public:
  ServoErrorMeasurer(const RobotModel& model, Eigen::VectorXd truth,
                     bool report_commanded)
      : model_(model), truth_(truth), report_commanded_(report_commanded) {}
  bool Measure(const MeasureBatch& batch, int k, PoseAnswer* answer,
               std::string*) override {
    const Eigen::VectorXd commanded = batch.joints.row(k).transpose();
    Eigen::VectorXd actual = commanded;
    for (Eigen::Index j = 0; j < actual.size(); ++j) {
      actual[j] += 0.02 * ((batch.poses[k] + j) % 3 - 1);
    }
    Measurement m;
    m.joints = report_commanded_ ? commanded : actual;
    m.position = MeasuredPoint(model_, truth_, actual);
    *answer = PoseAnswer();
    answer->measurements.push_back(m);
    return true;
  }

 private:
  const RobotModel& model_;
  Eigen::VectorXd truth_;
  bool report_commanded_;
};

TEST(ActiveLoopTest, TheMeasuredJointsAreIdentifiedFrom) {
  const Puma p;
  ActiveLoopOptions options = SmallLoop(p);
  options.first_batch = 40;
  options.max_rounds = 1;
  std::vector<Measurement> kept;
  options.round_callback = [&](const ActiveLoopState& s, std::string*) {
    kept = s.measurements;
    return true;
  };
  ServoErrorMeasurer reads(p.model, p.truth, false);
  ActiveLoopSummary summary;
  ASSERT_TRUE(RunActiveLoop(p.model, p.joints, p.joints, options, StridePoses,
                            &reads, nullptr, &summary))
      << summary.message;
  ASSERT_EQ(kept.size(), 40u);
  const int64_t first = summary.measured[0];
  EXPECT_NE(kept[0].joints, p.joints.row(first).transpose());
  EXPECT_LT(summary.rounds[0].residual_sigma_m, 1e-9);
  EXPECT_LT(summary.rounds[0].true_task_rms_m, 1e-8);

  ServoErrorMeasurer commanded(p.model, p.truth, true);
  ASSERT_TRUE(RunActiveLoop(p.model, p.joints, p.joints, options, StridePoses,
                            &commanded, nullptr, &summary));
  EXPECT_GT(summary.rounds[0].residual_sigma_m, 1e-4);
}

// Continuing from the state after any round gives the uninterrupted
// result bit for bit.
TEST(ActiveLoopTest, ResumingAfterAnyRoundGivesTheSameResult) {
  const Puma p;
  ActiveLoopOptions options = SmallLoop(p);
  options.max_rounds = 4;
  std::vector<ActiveLoopState> states;
  options.round_callback = [&](const ActiveLoopState& s, std::string*) {
    states.push_back(s);
    return true;
  };
  auto hidden = [](int64_t i) { return i % 5 == 2; };
  SimulatedMeasurer robot(p.model, p.truth, options.sigma_m, options.seed);
  robot.set_not_visible(hidden);
  ActiveLoopSummary whole;
  ASSERT_TRUE(RunActiveLoop(p.model, p.joints, p.joints, options, StridePoses,
                            &robot, nullptr, &whole))
      << whole.message;
  ASSERT_EQ(states.size(), 4u);
  options.round_callback = nullptr;
  for (size_t k = 0; k < states.size(); ++k) {
    SimulatedMeasurer fresh(p.model, p.truth, options.sigma_m, options.seed);
    fresh.set_not_visible(hidden);
    CountingMeasurer counting(&fresh);
    ActiveLoopSummary resumed;
    ASSERT_TRUE(RunActiveLoop(p.model, p.joints, p.joints, options, StridePoses,
                              &counting, &states[k], &resumed))
        << resumed.message;
    SCOPED_TRACE("resumed after round " + std::to_string(k));
    ExpectSameSummary(whole, resumed);
    // Nothing of the completed rounds is measured again.
    for (int64_t i : states[k].measured) EXPECT_EQ(counting.asked.count(i), 0u);
  }
  // A state that does not fit the pool is refused.
  ActiveLoopState bad = states[0];
  bad.measured.push_back(bad.measured[0]);
  bad.rounds[0].batch.push_back(bad.measured[0]);
  ActiveLoopSummary refused;
  EXPECT_FALSE(RunActiveLoop(p.model, p.joints, p.joints, options, StridePoses,
                             &robot, &bad, &refused));
  EXPECT_EQ(refused.termination_type, TerminationType::kUserFailure);
  EXPECT_NE(refused.message.find("twice"), std::string::npos)
      << refused.message;
}

// The identity the tests' PUMA sessions are made with.
const SessionIdentity kPumaIdentity = {{"seed", "1"}, {"robot", "puma"}};

// ActiveSession::Open with kPumaIdentity; a failure with its error.
::testing::AssertionResult OpenPumaSession(
    const std::string& dir, bool resume, const RobotModel& model,
    std::unique_ptr<ActiveSession>* session) {
  std::string error;
  if (ActiveSession::Open(dir, resume, model, kPumaIdentity, session, &error)) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << error;
}

// A session run in a directory, crashed by the cell mid-round (after
// `fail_after` answers, < 0: never), and continued until done; returns the
// final summary.
ActiveLoopSummary RunSession(const Puma& p, const std::string& dir, bool resume,
                             int fail_after,
                             std::vector<std::string>* notes = nullptr,
                             int* asked_again = nullptr,
                             const BatchSelector& select = StridePoses) {
  ActiveLoopOptions options = SmallLoop(p);
  std::unique_ptr<ActiveSession> session;
  EXPECT_TRUE(OpenPumaSession(dir, resume, p.model, &session));
  if (!session) return ActiveLoopSummary();
  if (notes) *notes = session->notes();
  std::set<int64_t> logged;
  if (resume) {
    // The poses measurements.csv holds: its pose_index column, third last.
    std::istringstream lines(ReadFile(session->MeasurementsPath()));
    std::string line;
    std::getline(lines, line);
    while (std::getline(lines, line)) {
      std::vector<std::string> fields;
      std::istringstream row(line);
      std::string field;
      while (std::getline(row, field, ',')) fields.push_back(field);
      logged.insert(std::stoll(fields[fields.size() - 3]));
    }
  }
  SimulatedMeasurer robot(p.model, p.truth, options.sigma_m, options.seed);
  robot.set_not_visible([](int64_t i) { return i % 4 == 1; });
  CountingMeasurer counting(&robot);
  counting.fail_after = fail_after;
  SessionMeasurer measurer(session.get(), &counting);
  options.round_callback = [&](const ActiveLoopState& s, std::string* e) {
    return session->SaveState(s, e);
  };
  ActiveLoopSummary summary;
  RunActiveLoop(p.model, p.joints, p.joints, options, select, &measurer,
                session->resume_state(), &summary);
  if (asked_again) {
    *asked_again = 0;
    for (const auto& kv : counting.asked)
      *asked_again += logged.count(kv.first);
  }
  return summary;
}

TEST(ActiveSessionTest, ACrashMidRoundLosesNothingAndResumesToTheSameBytes) {
  const Puma p;
  const std::string whole = TempDir("whole");
  const ActiveLoopSummary reference = RunSession(p, whole, false, -1);
  ASSERT_EQ(reference.termination_type, TerminationType::kNoConvergence)
      << reference.message;

  // Crashes at answer 44 (in round 1) and 5 answers into the second run.
  const std::string dir = TempDir("crashed");
  const ActiveLoopSummary first = RunSession(p, dir, false, 44);
  EXPECT_EQ(first.termination_type, TerminationType::kFailure);
  EXPECT_NE(first.message.find("the cell stopped"), std::string::npos);
  std::vector<std::string> notes;
  int asked_again = -1;
  const ActiveLoopSummary second =
      RunSession(p, dir, true, 5, &notes, &asked_again);
  EXPECT_EQ(second.termination_type, TerminationType::kFailure);
  EXPECT_EQ(asked_again, 0);
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes.back().find("continuing with round 1"), std::string::npos)
      << notes.back();
  const ActiveLoopSummary done =
      RunSession(p, dir, true, -1, &notes, &asked_again);
  EXPECT_EQ(asked_again, 0);
  ExpectSameSummary(reference, done);
  for (const char* f : {"measurements.csv", "excluded.jsonl", "state.json"}) {
    EXPECT_EQ(ReadFile(whole + "/" + f), ReadFile(dir + "/" + f)) << f;
  }
  // The log is a measurements file activecal_identify reads: one row per
  // measured pose, in measuring order.
  std::vector<Measurement> m;
  std::string error;
  ASSERT_TRUE(
      ReadMeasurementsCsv(dir + "/measurements.csv", p.model, &m, &error))
      << error;
  EXPECT_EQ(m.size(), done.measured.size());
}

// A last line cut by the crash is dropped with a note and that pose is
// measured again: the result is still the uninterrupted one.
TEST(ActiveSessionTest, ACutLastLineIsDroppedAndMeasuredAgain) {
  const Puma p;
  const std::string whole = TempDir("whole2");
  const ActiveLoopSummary reference = RunSession(p, whole, false, -1);
  const std::string dir = TempDir("cut");
  RunSession(p, dir, false, 20);
  const std::string path = dir + "/measurements.csv";
  std::string text = ReadFile(path);
  ASSERT_GT(text.size(), 10u);
  text.resize(text.size() - 7);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  std::vector<std::string> notes;
  const ActiveLoopSummary done = RunSession(p, dir, true, -1, &notes);
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes[0].find("dropped an unfinished last line"), std::string::npos)
      << notes[0];
  ExpectSameSummary(reference, done);
  EXPECT_EQ(ReadFile(whole + "/measurements.csv"), ReadFile(path));
}

// A continued loop that designs differently from the log (another build)
// is refused, not mixed with it.
TEST(ActiveSessionTest, ALoopThatLeavesTheLogIsRefused) {
  const Puma p;
  const std::string dir = TempDir("other");
  RunSession(p, dir, false, 44);  // crashed in round 1
  BatchSelector other = [](const CandidatePool& pool, const Eigen::MatrixXd& W,
                           const RowMatrixXd& prior, const BatchRequest& r,
                           std::vector<int64_t>* batch, std::string* error) {
    BatchRequest shifted = r;
    shifted.round = r.round + 40;  // other poses
    return StridePoses(pool, W, prior, shifted, batch, error);
  };
  const ActiveLoopSummary s =
      RunSession(p, dir, true, -1, nullptr, nullptr, other);
  EXPECT_EQ(s.termination_type, TerminationType::kFailure);
  EXPECT_NE(s.message.find("which the continued loop completed without "
                           "asking for it"),
            std::string::npos)
      << s.message;
}

TEST(ActiveSessionTest, ASessionIsContinuedOnlyAsItWasMade) {
  const Puma p;
  const std::string dir = TempDir("refuse");
  std::unique_ptr<ActiveSession> session;
  ASSERT_TRUE(OpenPumaSession(dir, false, p.model, &session));
  std::string error;
  // In use: a second process (here: a second open) is refused.
  std::unique_ptr<ActiveSession> twice;
  EXPECT_FALSE(
      ActiveSession::Open(dir, true, p.model, kPumaIdentity, &twice, &error));
  EXPECT_NE(error.find("in use by another activecal process"),
            std::string::npos)
      << error;
  session.reset();
  EXPECT_FALSE(ActiveSession::Open(dir, false, p.model, kPumaIdentity, &session,
                                   &error));
  EXPECT_NE(error.find("holds a session already"), std::string::npos) << error;
  const SessionIdentity other = {{"seed", "2"}, {"robot", "puma"}};
  EXPECT_FALSE(
      ActiveSession::Open(dir, true, p.model, other, &session, &error));
  EXPECT_NE(error.find("was made with seed 1, this run has 2"),
            std::string::npos)
      << error;
  const std::string empty = TempDir("empty");
  EXPECT_FALSE(ActiveSession::Open(empty, true, p.model, kPumaIdentity,
                                   &session, &error));
  EXPECT_NE(error.find("holds no session"), std::string::npos) << error;
}

TEST(ActiveSessionTest, TheStateReadsBackExactly) {
  ActiveLoopState s;
  s.round = 2;
  s.seed = 18446744073709551615ull;
  s.estimate = Eigen::Vector3d(0.1, -1.0 / 3.0, 1e-300);
  s.measured = {4, 9};
  ActiveRound r;
  r.batch = {4};
  r.excluded = {7};
  r.predicted_task_rms_m = std::numeric_limits<double>::infinity();
  r.true_task_rms_m = std::nan("");
  r.residual_sigma_m = 2.0 / 3.0;
  s.rounds = {r, r};
  s.rounds[1].batch = {9};
  ExcludedPose e;
  e.pose = 7;
  e.round = 0;
  e.status = "not_visible";
  e.message = "a \"quoted\", line";
  s.excluded = {e};
  ActiveLoopState back;
  std::string error;
  ASSERT_TRUE(
      ParseActiveLoopStateJson(ActiveLoopStateJson(s), "s.json", &back, &error))
      << error;
  EXPECT_EQ(back.round, 2);
  EXPECT_EQ(back.seed, s.seed);
  EXPECT_EQ(back.estimate, s.estimate);
  EXPECT_EQ(back.measured, s.measured);
  EXPECT_TRUE(std::isinf(back.rounds[0].predicted_task_rms_m));
  EXPECT_TRUE(std::isnan(back.rounds[0].true_task_rms_m));
  EXPECT_EQ(back.rounds[0].residual_sigma_m, 2.0 / 3.0);
  EXPECT_EQ(back.excluded[0].message, e.message);
  EXPECT_FALSE(
      ParseActiveLoopStateJson("{\"round\":1}", "s.json", &back, &error));
  EXPECT_NE(error.find("s.json: not a state activecal wrote"),
            std::string::npos);
}

}  // namespace
}  // namespace activecal
