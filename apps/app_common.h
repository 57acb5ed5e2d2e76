// Helpers shared by the activecal programs (not part of the library).

#ifndef ACTIVECAL_APPS_APP_COMMON_H_
#define ACTIVECAL_APPS_APP_COMMON_H_

#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "activecal/core/lattice.h"
#include "activecal/core/robot_model.h"
#include "activecal/selection/candidate_pool.h"
#include "activecal/selection/design.h"

namespace activecal {
namespace app {

// Prints "<program>: error: <message>" on stderr and exits with status 1.
[[noreturn]] void Fail(const std::string& message);

// Parses gflags and sets up glog; logs go to stderr, warnings and above.
void Init(int* argc, char*** argv, const char* usage);

// Writes text to path atomically: to a temporary file beside it, then
// renamed over it, so a failure never leaves a half-written file.
bool WriteFileAtomically(const std::string& path, const std::string& text,
                         std::string* error);
void WriteJsonOrDie(const std::string& path, const nlohmann::json& json);
void WriteTextOrDie(const std::string& path, const std::string& text);

// The lattice over the model with `levels` values per joint, and the
// Jacobian pool at `parameters`. Dies with a message on bad input.
JointLattice MakeLatticeOrDie(const RobotModel& model, int levels);
CandidatePool MakeLatticePoolOrDie(const RobotModel& model,
                                   const Eigen::VectorXd& parameters,
                                   const JointLattice& lattice, int num_threads,
                                   double* seconds);

// JSON for a selection result: algorithm, pool_size, pose_indices,
// joint_angles_rad, log10_det, oi, history_log10_det, seconds.
nlohmann::json SelectionJson(const SelectionSummary& summary,
                             const JointLattice& lattice);

// A stage line on stderr ("activecal_select: approximate design ..."),
// only when stderr is a terminal: logs and pipes stay clean.
void Progress(const std::string& message);

double Seconds(int64_t start_ns);
int64_t NowNs();

}  // namespace app
}  // namespace activecal

#endif  // ACTIVECAL_APPS_APP_COMMON_H_
