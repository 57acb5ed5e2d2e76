// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// A simulated robot cell (a robot and a tracker) on the driver side of the
// protocol (docs/driver_protocol.md): what activecal_sim_cell serves, on
// stdin/stdout or TCP, for trying activecal_active --driver without
// hardware and for testing the loop end to end through a real pipe.
//
//   SimulatedCellOptions options;
//   options.noise_m = 1e-4;
//   options.not_visible_fraction = 0.1;
//   SimulatedCell cell(model, truth, options, /*checker=*/nullptr);
//   LineChannel channel(STDIN_FILENO, STDOUT_FILENO);
//   int status = 0;
//   cell.Serve(&channel, &status);
//
// Every answer is seeded per pose (by the commanded joints and the seed),
// so the same pose always gets the same answer, whatever was asked before:
// tracker noise, occlusions, refused poses, the servo error. Only the drift
// depends on how many measurements were served. Notes and errors go to
// stderr, prefixed by options.program_name ("activecal_sim_cell: ...").

#ifndef ACTIVECAL_DRIVER_SIMULATED_CELL_H_
#define ACTIVECAL_DRIVER_SIMULATED_CELL_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "activecal/cell/cell_checker.h"
#include "activecal/core/robot_model.h"
#include "activecal/driver/connection.h"
#include "activecal/driver/protocol.h"

namespace activecal {

// Bad output of a driver at one measure request, to test activecal.
enum class DriverGarbage {
  kNone,
  kNotJson,        // a line that is not JSON
  kNan,            // a point with NaN, as Python's json.dumps writes it
  kWrongId,        // the reply to another request
  kWrongJoints,    // one joint too few
  kWrongMarkers,   // one point too many
  kUnknownStatus,  // "status":"done"
  kHang,           // no reply (an hour's wait)
  kExit,           // exit with status 4, no reply
  kLine,           // SimulatedCellOptions::garbage_line, as it is
};
// "none", "not_json", "nan", "wrong_id", "wrong_joints", "wrong_markers",
// "unknown_status", "hang", "exit", "line".
const char* DriverGarbageToString(DriverGarbage garbage);
// The kinds a user asks for: every name above but "none" and "line".
bool StringToDriverGarbage(const std::string& text, DriverGarbage* garbage);

struct SimulatedCellOptions {
  double noise_m = 1e-4;  // tracker noise per axis (m), >= 0
  // Report the marker frame's orientation too (a 6D probe), with this
  // noise per rotation-vector component (rad, >= 0).
  bool rotations = false;
  double rotation_noise_rad = 1e-4;
  bool report_sigma = false;     // send sigma_m (= noise_m) in replies
  double joint_noise_rad = 0.0;  // servo error per joint (rad or m), >= 0
  // Fractions of poses not seen / refused, drawn per pose, in [0, 1].
  double not_visible_fraction = 0.0;
  double unreachable_fraction = 0.0;
  double drift_m_per_measurement = 0.0;  // along x, per measurement served
  // Exit (status 3, no reply) at the measure request after this many
  // measurements were served; < 0: never.
  int64_t die_after = -1;
  double measure_delay_s = 0.0;  // wait before each reply, >= 0
  std::string served_log;        // append every reply sent (empty: none)
  // Answer measure request garbage_at (1-based) with bad output.
  DriverGarbage garbage = DriverGarbage::kNone;
  std::string garbage_line;  // the line of DriverGarbage::kLine
  int64_t garbage_at = 1;
  uint64_t seed = 1;
  // The cell's true robot: every free length (angle) parameter moved by a
  // Gaussian of this sigma (m, rad; >= 0) on top of the robot file's true
  // values, if any (MakeSimulatedCellTruth).
  double perturb_m = 0.0;
  double perturb_rad = 0.0;
  // Run: serve TCP on "PORT" or "HOST:PORT" (HOST default 127.0.0.1; PORT
  // 0: any free one), one client after another; empty: the given fds.
  std::string listen;
  // The cell's name: its driver name in the hello reply and the prefix of
  // its lines on stderr ("<program_name>: listening on 127.0.0.1:5000").
  std::string program_name = "simulated_cell";

  // The first option out of range, as "noise_m must be >= 0" (the names
  // are activecal_sim_cell's flags').
  bool IsValid(std::string* error) const;
};

class SimulatedCell {
 public:
  // checker (may be null, must outlive the cell): a marker is reported
  // only where the cell's checks see it (a pose where none is seen is
  // answered not_visible), when the checker's targets are the markers.
  SimulatedCell(RobotModel model, Eigen::VectorXd truth,
                SimulatedCellOptions options,
                const CellChecker* checker = nullptr);

  // Serves one conversation; false when the program must exit (with
  // *status).
  bool Serve(LineChannel* channel, int* status);
  // Serves the listener's clients one after another (first saying on
  // stderr where it listens) until a conversation ends the program (true,
  // *status); false with *error when a client cannot be accepted.
  bool ServeClients(TcpListener* listener, int* status, std::string* error);
  // What activecal_sim_cell runs: with options.listen, its socket made
  // (then `ready`, may be empty, is called: e.g. to write the files a run
  // that fails must not leave) and ServeClients; otherwise `ready` and one
  // conversation on in_fd/out_fd. True with *status when the program
  // should exit with it; false with *error ("--listen must be PORT or
  // HOST:PORT, got 'x'", "--listen: <why>", or why a client could not be
  // accepted).
  bool Run(int in_fd, int out_fd, const std::function<void()>& ready,
           int* status, std::string* error);

 private:
  bool Hello(const DriverHello& hello, LineChannel* channel, int* status);
  bool Send(const std::string& text, LineChannel* channel);
  bool Measure(const ActivecalMessage& request, LineChannel* channel,
               int* status);
  std::string Garbage(DriverGarbage kind, const ActivecalMessage& request,
                      MeasurementReply reply);
  void Answer(const Eigen::VectorXd& commanded, const std::vector<int>& markers,
              MeasurementReply* reply);

  RobotModel model_;
  Eigen::VectorXd truth_;
  SimulatedCellOptions options_;
  const CellChecker* checker_;
  std::unique_ptr<CellChecker::Workspace> workspace_;
  int64_t requests_ = 0;
  int64_t served_ = 0;
};

// The cell's true parameters: `true_parameters` (the robot file's; empty:
// none, then the nominal values) perturbed by options.perturb_m /
// perturb_rad (seeded by options.seed). False when there is nothing to
// simulate from (no true values, no perturbation) or the perturbation
// fails; *error is then worded for the flags ("robot has no true values:
// ...").
bool MakeSimulatedCellTruth(const RobotModel& model,
                            const Eigen::VectorXd& true_parameters,
                            const SimulatedCellOptions& options,
                            Eigen::VectorXd* truth, std::string* error);

// --listen's address: "PORT" or "HOST:PORT" (HOST default 127.0.0.1; PORT
// digits, 0..65535, 0: any free port). False with "must be PORT or
// HOST:PORT, got 'TEXT'" or "the port must be in 0..65535, got 'PORT'".
bool ParseListenAddress(const std::string& text, std::string* host, int* port,
                        std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_DRIVER_SIMULATED_CELL_H_
