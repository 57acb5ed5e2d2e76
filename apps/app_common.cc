#include "app_common.h"

#include <gflags/gflags.h>
#include <glog/logging.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "activecal/residuals/jacobians.h"
#include "activecal/selection/criteria.h"

namespace activecal {
namespace app {
namespace {
std::string g_program = "activecal";
}

void Fail(const std::string& message) {
  std::cerr << g_program << ": error: " << message << std::endl;
  std::exit(1);
}

void Init(int* argc, char*** argv, const char* usage) {
  g_program = (*argv)[0];
  const size_t slash = g_program.rfind('/');
  if (slash != std::string::npos) g_program = g_program.substr(slash + 1);
  gflags::SetUsageMessage(usage);
  gflags::SetVersionString("0.1.0");
  gflags::ParseCommandLineFlags(argc, argv, true);
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = 1;
  google::InitGoogleLogging((*argv)[0]);
  if (*argc > 1) {
    Fail(std::string("unexpected argument '") + (*argv)[1] +
         "' (flags are written --name=value; see --help)");
  }
}

bool WriteFileAtomically(const std::string& path, const std::string& text,
                         std::string* error) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      *error = "cannot open '" + tmp + "' for writing";
      return false;
    }
    out << text;
    out.flush();
    if (!out) {
      *error = "failed writing '" + tmp + "'";
      std::remove(tmp.c_str());
      return false;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    *error = "cannot rename '" + tmp + "' to '" + path + "'";
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

void WriteTextOrDie(const std::string& path, const std::string& text) {
  std::string error;
  if (!WriteFileAtomically(path, text, &error)) Fail(error);
}

void WriteJsonOrDie(const std::string& path, const nlohmann::json& json) {
  WriteTextOrDie(path, json.dump(2) + "\n");
}

JointLattice MakeLatticeOrDie(const RobotModel& model, int levels) {
  JointLattice lattice;
  std::string error;
  if (!JointLattice::Create(model, levels, &lattice, &error)) {
    Fail("--levels=" + std::to_string(levels) + ": " + error);
  }
  return lattice;
}

CandidatePool MakeLatticePoolOrDie(const RobotModel& model,
                                   const Eigen::VectorXd& parameters,
                                   const JointLattice& lattice, int num_threads,
                                   double* seconds) {
  const int64_t start = NowNs();
  Progress("Jacobians of " + std::to_string(lattice.size()) + " poses ...");
  RowMatrixXd stacked;
  std::string error;
  PoolJacobianOptions options;
  options.num_threads = num_threads;
  if (!PoolPositionJacobians(model, parameters, lattice.AllJointValues(),
                             options, &stacked, &error)) {
    Fail(error);
  }
  CandidatePool pool;
  if (!CandidatePool::Create(std::move(stacked), 3, &pool, &error)) {
    Fail(error);
  }
  if (seconds) *seconds = Seconds(start);
  return pool;
}

nlohmann::json SelectionJson(const SelectionSummary& summary,
                             const JointLattice& lattice) {
  nlohmann::json j;
  j["algorithm"] = summary.algorithm;
  j["pool_size"] = summary.pool_size;
  j["num_parameters"] = summary.num_parameters;
  j["pose_indices"] = summary.design;
  nlohmann::json angles = nlohmann::json::array();
  for (int64_t i : summary.design) {
    const Eigen::VectorXd q = lattice.JointValues(i);
    angles.push_back(std::vector<double>(q.data(), q.data() + q.size()));
  }
  j["joint_angles_rad"] = angles;
  j["log10_det"] = summary.log10_det();
  j["oi"] = OiFromLogDet(summary.log_det, summary.num_parameters);
  std::vector<double> history;
  for (const SelectionStep& s : summary.history) {
    history.push_back(s.log_det / std::log(10.0));
  }
  j["history_log10_det"] = history;
  j["seconds"] = summary.seconds;
  return j;
}

void Progress(const std::string& message) {
  static const bool tty = isatty(2);
  if (tty) std::cerr << g_program << ": " << message << std::endl;
}

int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double Seconds(int64_t start_ns) { return (NowNs() - start_ns) * 1e-9; }

}  // namespace app
}  // namespace activecal
