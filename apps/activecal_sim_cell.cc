// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_sim_cell: a simulated robot cell (a robot and a tracker) that
// speaks the driver protocol (docs/driver_protocol.md) on stdin/stdout, or
// on TCP with --listen, for trying activecal_active --driver without
// hardware and for testing the loop end to end through a real pipe.
//
// The cell's robot is --robot with its true values ('true:' entries), or a
// robot (a URDF) whose parameters --perturb_m / --perturb_rad move by
// seeded Gaussian amounts (--truth_out writes the robot file with those
// true values, for activecal_active to report the true error). Every
// answer is seeded per pose (by the commanded joints and --seed), so the
// same pose always gets the same answer, whatever was asked before:
// tracker noise, occlusions, refused poses, the servo error. Only the drift
// (--drift_m_per_measurement) depends on how many measurements were served.

#include <gflags/gflags.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <thread>

#include "activecal/calibration/cell_planning.h"
#include "activecal/calibration/pool_builder.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/driver/connection.h"
#include "activecal/driver/protocol.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/robot_loader.h"
#include "app_common.h"

DEFINE_double(noise_m, 1e-4, "Tracker noise per axis (m), >= 0.");
DEFINE_bool(rotations, false,
            "Report the marker frame's orientation too (a 6D probe): "
            "\"rotations\" in the reply.");
DEFINE_double(rotation_noise_rad, 1e-4,
              "With --rotations: noise of each rotation-vector component "
              "(rad).");
DEFINE_bool(report_sigma, false, "Send sigma_m (= --noise_m) in replies.");
DEFINE_double(joint_noise_rad, 0.0,
              "Servo error: the robot stops this far (Gaussian per joint, "
              "rad or m) from the commanded joints; the encoders read where "
              "it stopped (the reply's joints_rad).");
DEFINE_double(perturb_m, 0.0,
              "Move every free length parameter of --robot by a Gaussian of "
              "this sigma (m) to make the cell's true robot (on top of the "
              "file's true values, if any).");
DEFINE_double(perturb_rad, 0.0,
              "The same for every free angle parameter (rad).");
DEFINE_string(truth_out, "",
              "Write the cell's robot (nominal values and true values) as "
              "an activecal robot file here.");
DEFINE_double(not_visible_fraction, 0.0,
              "Fraction of poses the tracker cannot see (status "
              "not_visible), drawn per pose.");
DEFINE_double(unreachable_fraction, 0.0,
              "Fraction of poses the robot refuses (status unreachable), "
              "drawn per pose.");
DEFINE_double(drift_m_per_measurement, 0.0,
              "Tracker drift: every point moves by this much (m, along x) "
              "per measurement served.");
DEFINE_int64(die_after, -1,
             "Exit (status 3, no reply) at the measure request after this "
             "many measurements were served; < 0: never.");
DEFINE_double(measure_delay_s, 0.0,
              "Wait this long before each reply (the robot moving).");
DEFINE_string(listen, "",
              "Serve TCP on PORT or HOST:PORT (HOST default 127.0.0.1; PORT "
              "0: any free one, printed on stderr) instead of stdin/stdout, "
              "one client after another.");
DEFINE_string(served_log, "",
              "Append every reply sent to this file (one JSON line each).");
DEFINE_string(garbage, "",
              "Answer measure request --garbage_at with bad output, to test "
              "activecal: not_json, nan, wrong_id, wrong_joints, "
              "wrong_markers, unknown_status, hang (no reply), exit.");
DEFINE_int64(garbage_at, 1, "Which measure request (1-based) --garbage hits.");
DEFINE_uint64(seed, 1, "Seed of the perturbation and of every answer.");

namespace activecal {
namespace {

// The protocol's output: the real stdout, kept aside so that nothing else
// the program prints (robot notes) reaches activecal.
int g_protocol_out = -1;

uint64_t PoseHash(const Eigen::VectorXd& q) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a over the doubles' bytes
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    const double v = q[i] == 0 ? 0.0 : q[i];  // -0 and 0 are one pose
    unsigned char bytes[sizeof(double)];
    std::memcpy(bytes, &v, sizeof(v));
    for (unsigned char b : bytes) {
      h ^= b;
      h *= 1099511628211ull;
    }
  }
  return h;
}

DEFINE_string(cell, "",
              "A cell file (docs/formats.md): its targets are the robot's "
              "markers (unless --frames gives them), and a marker is "
              "reported only where the cell's checks see it (a pose where "
              "none is seen is answered not_visible), as activecal_active "
              "--cell plans.");

class Cell {
 public:
  Cell(RobotModel model, Eigen::VectorXd truth,
       const CellChecker* checker = nullptr)
      : model_(std::move(model)),
        truth_(std::move(truth)),
        checker_(checker),
        workspace_(checker ? checker->NewWorkspace() : nullptr) {}

  // Serves one conversation; false when the program must exit (with
  // *status).
  bool Serve(LineChannel* channel, int* status) {
    std::string line, error;
    for (;;) {
      const LineChannel::ReadResult r = channel->ReadLine(0, &line, &error);
      if (r != LineChannel::ReadResult::kLine) return true;  // client gone
      ActivecalMessage message;
      if (!ParseActivecalMessage(line, &message, &error)) {
        std::fprintf(stderr, "activecal_sim_cell: %s\n", error.c_str());
        continue;
      }
      switch (message.type) {
        case ActivecalMessageType::kBye:
          return true;
        case ActivecalMessageType::kHello:
          if (!Hello(message.hello, channel, status)) return false;
          break;
        case ActivecalMessageType::kMeasure:
          if (!Measure(message, channel, status)) return false;
          break;
      }
    }
  }

 private:
  bool Hello(const DriverHello& hello, LineChannel* channel, int* status) {
    if (static_cast<int>(hello.joint_names.size()) != model_.num_joints() ||
        hello.markers != model_.num_markers()) {
      std::fprintf(stderr,
                   "activecal_sim_cell: activecal's robot has %zu joints "
                   "and %d markers, the cell's '%s' %d and %d\n",
                   hello.joint_names.size(), hello.markers, model_.name.c_str(),
                   model_.num_joints(), model_.num_markers());
      *status = 2;
      return false;
    }
    char about[512];
    std::snprintf(about, sizeof(about),
                  "{\"driver\":\"activecal_sim_cell\",\"robot\":\"%s\","
                  "\"noise_m\":%.17g,\"seed\":%llu}",
                  model_.name.c_str(), FLAGS_noise_m,
                  static_cast<unsigned long long>(FLAGS_seed));
    return Send(DriverHelloMessage(about), channel);
  }

  bool Send(const std::string& text, LineChannel* channel) {
    std::string error;
    if (!channel->WriteLine(text, &error)) {
      std::fprintf(stderr, "activecal_sim_cell: cannot reply: %s\n",
                   error.c_str());
      return true;  // the client has gone; the next read says so
    }
    if (!FLAGS_served_log.empty()) {
      std::ofstream log(FLAGS_served_log, std::ios::app);
      log << text << "\n";
    }
    return true;
  }

  bool Measure(const ActivecalMessage& request, LineChannel* channel,
               int* status) {
    ++requests_;
    if (FLAGS_die_after >= 0 && served_ >= FLAGS_die_after) {
      std::fprintf(stderr,
                   "activecal_sim_cell: dying after %lld measurements "
                   "(--die_after)\n",
                   static_cast<long long>(served_));
      *status = 3;
      return false;
    }
    if (FLAGS_measure_delay_s > 0) {
      std::this_thread::sleep_for(
          std::chrono::duration<double>(FLAGS_measure_delay_s));
    }
    MeasurementReply reply;
    reply.id = request.id;
    Answer(request.joints, request.markers, &reply);
    std::string text = MeasurementReplyMessage(reply);
    if (!FLAGS_garbage.empty() && requests_ == FLAGS_garbage_at) {
      const std::string& g = FLAGS_garbage;
      if (g == "exit") {
        *status = 4;
        return false;
      }
      if (g == "hang") {
        std::this_thread::sleep_for(std::chrono::hours(1));
      }
      text = Garbage(g, request, reply);
    }
    ++served_;
    return Send(text, channel);
  }

  static std::string Garbage(const std::string& kind,
                             const ActivecalMessage& request,
                             MeasurementReply reply) {
    if (kind == "not_json") return "moving to pose " + std::to_string(reply.id);
    if (kind == "wrong_id") {
      reply.id = request.id + 1;
      return MeasurementReplyMessage(reply);
    }
    if (kind == "unknown_status") {
      std::string t = MeasurementReplyMessage(reply);
      const std::string s = "\"status\":\"";
      const size_t at = t.find(s);
      const size_t end = t.find('"', at + s.size());
      return t.substr(0, at + s.size()) + "done" + t.substr(end);
    }
    reply.status = MeasureStatus::kOk;
    if (reply.joints.size() == 0) reply.joints = request.joints;
    if (reply.points_m.empty() || !reply.points_m[0]) {
      reply.points_m.assign(1, Eigen::Vector3d(0.5, 0.1, 0.2));
    }
    if (kind == "wrong_joints") {
      reply.joints.conservativeResize(reply.joints.size() - 1);
      return MeasurementReplyMessage(reply);
    }
    if (kind == "wrong_markers") {
      reply.points_m.push_back(reply.points_m[0]);
      return MeasurementReplyMessage(reply);
    }
    if (kind == "nan") {
      // What Python's json.dumps writes for a float('nan').
      std::string t = MeasurementReplyMessage(reply);
      const size_t at = t.find("\"points_m\":[[") + 13;
      const size_t end = t.find(',', at);
      return t.substr(0, at) + "NaN" + t.substr(end);
    }
    return "garbage kind '" + kind + "' unknown";
  }

  // markers: those asked for (empty: every marker); the others are
  // answered null, as a tracker that was not pointed at them.
  void Answer(const Eigen::VectorXd& commanded, const std::vector<int>& markers,
              MeasurementReply* reply) {
    if (commanded.size() != model_.num_joints()) {
      reply->status = MeasureStatus::kError;
      reply->message = "expected " + std::to_string(model_.num_joints()) +
                       " joints, got " + std::to_string(commanded.size());
      return;
    }
    const uint64_t pose_seed =
        Random::StreamSeed(FLAGS_seed, PoseHash(commanded));
    Random random(pose_seed);
    const double visible = random.Uniform();
    const double reachable = random.Uniform();
    if (reachable < FLAGS_unreachable_fraction) {
      reply->status = MeasureStatus::kUnreachable;
      reply->message = "simulated: outside the cell's workspace";
      return;
    }
    if (visible < FLAGS_not_visible_fraction) {
      reply->status = MeasureStatus::kNotVisible;
      reply->message = "simulated: the tracker's line of sight is blocked";
      return;
    }
    Eigen::VectorXd actual = commanded;
    for (Eigen::Index j = 0; j < actual.size(); ++j) {
      actual[j] += FLAGS_joint_noise_rad * random.Gaussian();
    }
    for (int k : markers) {
      if (k >= model_.num_markers()) {
        reply->status = MeasureStatus::kError;
        reply->message = "marker " + std::to_string(k) + " asked for, the " +
                         "robot has " + std::to_string(model_.num_markers());
        return;
      }
    }
    // The cell's verdict at the commanded pose: the targets it sees.
    uint32_t seen = ~0u;
    if (checker_) {
      const PoseVerdict v = checker_->Check(commanded.data(), workspace_.get());
      if (v.targets_seen == 0) {
        reply->status = MeasureStatus::kNotVisible;
        reply->message = "simulated cell: " + checker_->Describe(v);
        return;
      }
      if (checker_->num_targets() == model_.num_markers()) {
        seen = v.targets_seen;
      }
    }
    auto asked = [&](int k) {
      return (k >= 32 || (seen & (1u << k))) &&
             (markers.empty() ||
              std::find(markers.begin(), markers.end(), k) != markers.end());
    };
    bool any = false;
    for (int k = 0; k < model_.num_markers(); ++k) any = any || asked(k);
    if (!any) {
      reply->status = MeasureStatus::kNotVisible;
      reply->message = "simulated cell: no marker asked for is seen";
      return;
    }
    std::vector<Measurement> plan;
    for (int k = 0; k < model_.num_markers(); ++k) {
      Measurement m;
      m.type =
          FLAGS_rotations ? MeasurementType::kPose : MeasurementType::kPosition;
      m.joints = actual;
      m.marker = k;
      plan.push_back(m);
    }
    SimulationNoise noise;
    noise.position_m = FLAGS_noise_m;
    noise.rotation_rad = FLAGS_rotation_noise_rad;
    std::vector<Measurement> measured;
    std::string error;
    if (!SimulateMeasurements(model_, truth_, plan, noise,
                              Random::StreamSeed(pose_seed, 1), &measured,
                              &error)) {
      reply->status = MeasureStatus::kError;
      reply->message = error;
      return;
    }
    reply->status = MeasureStatus::kOk;
    reply->joints = actual;
    const Eigen::Vector3d drift(
        FLAGS_drift_m_per_measurement * static_cast<double>(served_), 0, 0);
    for (const Measurement& m : measured) {
      // Every marker is simulated (the noise does not depend on which are
      // asked for); those not asked for, or not seen, are not reported.
      if (!asked(m.marker)) {
        reply->points_m.push_back(std::nullopt);
        if (FLAGS_rotations) reply->rotations.push_back(std::nullopt);
        continue;
      }
      reply->points_m.push_back(m.position + drift);
      if (FLAGS_rotations) reply->rotations.push_back(m.rotation);
    }
    if (FLAGS_report_sigma && FLAGS_noise_m > 0) reply->sigma_m = FLAGS_noise_m;
  }

  RobotModel model_;
  Eigen::VectorXd truth_;
  const CellChecker* checker_;
  std::unique_ptr<CellChecker::Workspace> workspace_;
  int64_t requests_ = 0;
  int64_t served_ = 0;
};

int Main() {
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"noise_m", FLAGS_noise_m},
        {"rotation_noise_rad", FLAGS_rotation_noise_rad},
        {"joint_noise_rad", FLAGS_joint_noise_rad},
        {"perturb_m", FLAGS_perturb_m},
        {"perturb_rad", FLAGS_perturb_rad},
        {"measure_delay_s", FLAGS_measure_delay_s}}) {
    if (!(value >= 0) || !std::isfinite(value)) {
      app::Fail(std::string("--") + name + " must be >= 0");
    }
  }
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"not_visible_fraction",
                                       FLAGS_not_visible_fraction},
        {"unreachable_fraction", FLAGS_unreachable_fraction}}) {
    if (!(value >= 0 && value <= 1)) {
      app::Fail(std::string("--") + name + " must be in [0, 1]");
    }
  }
  RobotDescription robot = app::LoadRobotOrDie();
  // The cell: its targets as the markers (before the truth is read); its
  // notes on stderr (stdout may be the protocol's channel).
  CellSetup cell_setup;
  if (!FLAGS_cell.empty()) {
    CellSetupOptions options;
    options.cell_path = FLAGS_cell;
    options.robot_path = FLAGS_robot;
    options.chain.base_link = FLAGS_base_link;
    options.chain.tip_link = FLAGS_tip_link;
    options.targets_as_markers = FLAGS_frames.empty();
    std::string error;
    if (!SetUpCell(options, &robot, &cell_setup, &error)) {
      app::Fail("--cell: " + error);
    }
    for (const std::string& note : cell_setup.notes) {
      std::fprintf(stderr, "activecal_sim_cell: --cell: note: %s\n",
                   note.c_str());
    }
  }
  RobotModel& model = robot.model;
  const bool urdf = !FLAGS_robot.empty() && IsUrdfPath(FLAGS_robot);
  if (urdf || !FLAGS_parameter_set.empty()) {
    const JointLattice lattice = app::MakeLatticeOrDie(model, 3);
    const Eigen::MatrixXd joints = lattice.AllJointValues();
    // Several markers (the cell's targets, or a frames file's): the
    // simulated robot's truth is every marker's, each measured at every
    // pose of the lattice (marker 0's alone held the others' offsets).
    std::vector<uint32_t> every_marker;
    if (model.num_markers() > 1) {
      every_marker.assign(joints.rows(), EveryMarkerMask(model));
    }
    model =
        WithFreeSet(model, app::ReducedParameterSetOrDie(
                               model, urdf, joints,
                               every_marker.empty() ? nullptr : &every_marker));
  }
  Eigen::VectorXd truth = robot.true_parameters.size() == model.num_parameters()
                              ? robot.true_parameters
                              : model.nominal;
  const bool perturbed = FLAGS_perturb_m > 0 || FLAGS_perturb_rad > 0;
  if (robot.true_parameters.size() != model.num_parameters() && !perturbed) {
    app::Fail(
        "--robot has no true values: add 'true:' entries (docs/formats.md) "
        "or perturb it (--perturb_m, --perturb_rad)");
  }
  if (perturbed) {
    std::string error;
    const Eigen::VectorXd unperturbed = truth;
    if (!PerturbParameters(model, unperturbed, FLAGS_perturb_m,
                           FLAGS_perturb_rad, FLAGS_seed, &truth, &error)) {
      app::Fail("--" + error);
    }
  }
  // --listen's socket before --truth_out is written: a run that fails
  // writes nothing.
  std::unique_ptr<TcpListener> listener;
  std::string host = "127.0.0.1";
  if (!FLAGS_listen.empty()) {
    std::string port = FLAGS_listen;
    const size_t colon = FLAGS_listen.rfind(':');
    if (colon != std::string::npos) {
      host = FLAGS_listen.substr(0, colon);
      port = FLAGS_listen.substr(colon + 1);
    }
    if (port.empty() || port.find_first_not_of("0123456789") != port.npos) {
      app::Fail("--listen must be PORT or HOST:PORT, got '" + FLAGS_listen +
                "'");
    }
    std::string error;
    if (!TcpListener::Listen(host, std::stoi(port), &listener, &error)) {
      app::Fail("--listen: " + error);
    }
  }
  if (!FLAGS_truth_out.empty()) {
    RobotFileOptions options;
    options.true_parameters = truth;
    options.comment =
        "The robot of activecal_sim_cell --seed=" + std::to_string(FLAGS_seed) +
        " (nominal values and the cell's true values)";
    app::WriteTextOrDie(FLAGS_truth_out,
                        RobotFileText(model, model.nominal, options));
    app::CommitOutputsOrDie();  // read while the cell serves
  }
  Cell cell(model, truth, cell_setup.checker.get());
  int status = 0;
  if (!listener) {
    LineChannel channel(STDIN_FILENO, g_protocol_out);
    cell.Serve(&channel, &status);
    return status;
  }
  std::fprintf(stderr, "activecal_sim_cell: listening on %s:%d\n", host.c_str(),
               listener->port());
  for (;;) {
    std::unique_ptr<LineChannel> channel;
    std::string error;
    if (!listener->Accept(&channel, &error)) app::Fail(error);
    if (!cell.Serve(channel.get(), &status)) return status;
  }
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  // The protocol owns the real stdout; everything else goes to stderr.
  activecal::g_protocol_out = dup(STDOUT_FILENO);
  dup2(STDERR_FILENO, STDOUT_FILENO);
  activecal::app::Init(
      &argc, &argv,
      "A simulated robot cell speaking activecal's driver protocol "
      "(docs/driver_protocol.md) on stdin/stdout, or TCP with --listen: the "
      "robot of --robot with its true values (or perturbed: --perturb_m, "
      "--perturb_rad), tracker noise, occlusions, refused poses, drift, and "
      "a crash on demand (--die_after).\n"
      "  activecal_active --driver=\"activecal_sim_cell --seed=3 "
      "--not_visible_fraction=0.1\" --session=run1");
  return activecal::app::Finish(activecal::Main());
}
