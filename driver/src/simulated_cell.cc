// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/driver/simulated_cell.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "activecal/core/enum_name_list.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"

namespace activecal {
namespace {

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

}  // namespace

constexpr const char* kDriverGarbageNames[] = {
    "none",          "not_json",       "nan",  "wrong_id", "wrong_joints",
    "wrong_markers", "unknown_status", "hang", "exit",     "line"};

const char* DriverGarbageToString(DriverGarbage garbage) {
  return EnumToString(kDriverGarbageNames, garbage);
}

bool StringToDriverGarbage(const std::string& text, DriverGarbage* garbage) {
  DriverGarbage named;
  // The kinds a user asks for: not "none", nor "line" (garbage_line's).
  if (!StringToEnum(kDriverGarbageNames, text, &named) ||
      named == DriverGarbage::kNone || named == DriverGarbage::kLine) {
    return false;
  }
  *garbage = named;
  return true;
}

bool SimulatedCellOptions::IsValid(std::string* error) const {
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"noise_m", noise_m},
        {"rotation_noise_rad", rotation_noise_rad},
        {"joint_noise_rad", joint_noise_rad},
        {"perturb_m", perturb_m},
        {"perturb_rad", perturb_rad},
        {"measure_delay_s", measure_delay_s}}) {
    if (!(value >= 0) || !std::isfinite(value)) {
      *error = std::string(name) + " must be >= 0";
      return false;
    }
  }
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"not_visible_fraction",
                                       not_visible_fraction},
        {"unreachable_fraction", unreachable_fraction}}) {
    if (!(value >= 0 && value <= 1)) {
      *error = std::string(name) + " must be in [0, 1]";
      return false;
    }
  }
  return true;
}

bool MakeSimulatedCellTruth(const RobotModel& model,
                            const Eigen::VectorXd& true_parameters,
                            const SimulatedCellOptions& options,
                            Eigen::VectorXd* truth, std::string* error) {
  const bool known = true_parameters.size() == model.num_parameters();
  *truth = known ? true_parameters : model.nominal;
  const bool perturbed = options.perturb_m > 0 || options.perturb_rad > 0;
  if (!known && !perturbed) {
    *error =
        "robot has no true values: add 'true:' entries (docs/formats.md) "
        "or perturb it (--perturb_m, --perturb_rad)";
    return false;
  }
  if (perturbed) {
    const Eigen::VectorXd unperturbed = *truth;
    if (!PerturbParameters(model, unperturbed, options.perturb_m,
                           options.perturb_rad, options.seed, truth, error)) {
      return false;
    }
  }
  return true;
}

bool ParseListenAddress(const std::string& text, std::string* host, int* port,
                        std::string* error) {
  std::string digits = text;
  *host = "127.0.0.1";
  const size_t colon = text.rfind(':');
  if (colon != std::string::npos) {
    *host = text.substr(0, colon);
    digits = text.substr(colon + 1);
  }
  if (digits.empty() ||
      digits.find_first_not_of("0123456789") != std::string::npos) {
    *error = "must be PORT or HOST:PORT, got '" + text + "'";
    return false;
  }
  // A port is 16 bits: 70000 is refused, not taken modulo 65536.
  if (digits.size() > 5 || std::stoi(digits) > 65535) {
    *error = "the port must be in 0..65535, got '" + digits + "'";
    return false;
  }
  *port = std::stoi(digits);
  return true;
}

SimulatedCell::SimulatedCell(RobotModel model, Eigen::VectorXd truth,
                             SimulatedCellOptions options,
                             const CellChecker* checker)
    : model_(std::move(model)),
      truth_(std::move(truth)),
      options_(std::move(options)),
      checker_(checker),
      workspace_(checker ? checker->NewWorkspace() : nullptr) {}

bool SimulatedCell::Serve(LineChannel* channel, int* status) {
  std::string line, error;
  for (;;) {
    const LineChannel::ReadResult r = channel->ReadLine(0, &line, &error);
    if (r != LineChannel::ReadResult::kLine) return true;  // client gone
    ActivecalMessage message;
    if (!ParseActivecalMessage(line, &message, &error)) {
      std::fprintf(stderr, "%s: %s\n", options_.program_name.c_str(),
                   error.c_str());
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

bool SimulatedCell::ServeClients(TcpListener* listener, int* status,
                                 std::string* error) {
  std::fprintf(stderr, "%s: listening on %s:%d\n",
               options_.program_name.c_str(), listener->host().c_str(),
               listener->port());
  for (;;) {
    std::unique_ptr<LineChannel> channel;
    if (!listener->Accept(&channel, error)) return false;
    if (!Serve(channel.get(), status)) return true;
  }
}

bool SimulatedCell::Run(int in_fd, int out_fd,
                        const std::function<void()>& ready, int* status,
                        std::string* error) {
  *status = 0;
  if (options_.listen.empty()) {
    if (ready) ready();
    LineChannel channel(in_fd, out_fd);
    Serve(&channel, status);
    return true;
  }
  std::string host = "127.0.0.1";
  int port = 0;
  std::unique_ptr<TcpListener> listener;
  if (!ParseListenAddress(options_.listen, &host, &port, error)) {
    *error = "--listen " + *error;
    return false;
  }
  if (!TcpListener::Listen(host, port, &listener, error)) {
    *error = "--listen: " + *error;
    return false;
  }
  if (ready) ready();
  return ServeClients(listener.get(), status, error);
}

bool SimulatedCell::Hello(const DriverHello& hello, LineChannel* channel,
                          int* status) {
  if (static_cast<int>(hello.joint_names.size()) != model_.num_joints() ||
      hello.markers != model_.num_markers()) {
    std::fprintf(stderr,
                 "%s: activecal's robot has %zu joints "
                 "and %d markers, the cell's '%s' %d and %d\n",
                 options_.program_name.c_str(), hello.joint_names.size(),
                 hello.markers, model_.name.c_str(), model_.num_joints(),
                 model_.num_markers());
    *status = 2;
    return false;
  }
  // Made as JSON (not printed into a format): a program or robot name with
  // a quote or a backslash stays a string.
  const nlohmann::ordered_json about = {
      {"driver", options_.program_name},
      {"robot", model_.name},
      {"noise_m", options_.noise_m},
      {"seed", static_cast<unsigned long long>(options_.seed)}};
  return Send(DriverHelloMessage(about.dump()), channel);
}

bool SimulatedCell::Send(const std::string& text, LineChannel* channel) {
  std::string error;
  if (!channel->WriteLine(text, &error)) {
    std::fprintf(stderr, "%s: cannot reply: %s\n",
                 options_.program_name.c_str(), error.c_str());
    return true;  // the client has gone; the next read says so
  }
  if (!options_.served_log.empty()) {
    std::ofstream log(options_.served_log, std::ios::app);
    log << text << "\n";
  }
  return true;
}

bool SimulatedCell::Measure(const ActivecalMessage& request,
                            LineChannel* channel, int* status) {
  ++requests_;
  if (options_.die_after >= 0 && served_ >= options_.die_after) {
    std::fprintf(stderr,
                 "%s: dying after %lld measurements "
                 "(--die_after)\n",
                 options_.program_name.c_str(),
                 static_cast<long long>(served_));
    *status = 3;
    return false;
  }
  if (options_.measure_delay_s > 0) {
    std::this_thread::sleep_for(
        std::chrono::duration<double>(options_.measure_delay_s));
  }
  MeasurementReply reply;
  reply.id = request.id;
  Answer(request.joints, request.markers, &reply);
  std::string text = MeasurementReplyMessage(reply);
  if (options_.garbage != DriverGarbage::kNone &&
      requests_ == options_.garbage_at) {
    const DriverGarbage g = options_.garbage;
    if (g == DriverGarbage::kExit) {
      *status = 4;
      return false;
    }
    if (g == DriverGarbage::kHang) {
      std::this_thread::sleep_for(std::chrono::hours(1));
    }
    text = Garbage(g, request, reply);
  }
  ++served_;
  return Send(text, channel);
}

std::string SimulatedCell::Garbage(DriverGarbage kind,
                                   const ActivecalMessage& request,
                                   MeasurementReply reply) {
  if (kind == DriverGarbage::kNotJson)
    return "moving to pose " + std::to_string(reply.id);
  if (kind == DriverGarbage::kWrongId) {
    reply.id = request.id + 1;
    return MeasurementReplyMessage(reply);
  }
  if (kind == DriverGarbage::kUnknownStatus) {
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
  if (kind == DriverGarbage::kWrongJoints) {
    reply.joints.conservativeResize(reply.joints.size() - 1);
    return MeasurementReplyMessage(reply);
  }
  if (kind == DriverGarbage::kWrongMarkers) {
    reply.points_m.push_back(reply.points_m[0]);
    return MeasurementReplyMessage(reply);
  }
  if (kind == DriverGarbage::kNan) {
    // What Python's json.dumps writes for a float('nan').
    std::string t = MeasurementReplyMessage(reply);
    const size_t at = t.find("\"points_m\":[[") + 13;
    const size_t end = t.find(',', at);
    return t.substr(0, at) + "NaN" + t.substr(end);
  }
  if (kind == DriverGarbage::kLine) return options_.garbage_line;
  return std::string("garbage kind '") + DriverGarbageToString(kind) +
         "' unknown";
}

// markers: those asked for (empty: every marker); the others are
// answered null, as a tracker that was not pointed at them.
void SimulatedCell::Answer(const Eigen::VectorXd& commanded,
                           const std::vector<int>& markers,
                           MeasurementReply* reply) {
  if (commanded.size() != model_.num_joints()) {
    reply->status = MeasureStatus::kError;
    reply->message = "expected " + std::to_string(model_.num_joints()) +
                     " joints, got " + std::to_string(commanded.size());
    return;
  }
  const uint64_t pose_seed =
      Random::StreamSeed(options_.seed, PoseHash(commanded));
  Random random(pose_seed);
  const double visible = random.Uniform();
  const double reachable = random.Uniform();
  if (reachable < options_.unreachable_fraction) {
    reply->status = MeasureStatus::kUnreachable;
    reply->message = "simulated: outside the cell's workspace";
    return;
  }
  if (visible < options_.not_visible_fraction) {
    reply->status = MeasureStatus::kNotVisible;
    reply->message = "simulated: the tracker's line of sight is blocked";
    return;
  }
  Eigen::VectorXd actual = commanded;
  for (Eigen::Index j = 0; j < actual.size(); ++j) {
    actual[j] += options_.joint_noise_rad * random.Gaussian();
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
    m.type = options_.rotations ? MeasurementType::kPose
                                : MeasurementType::kPosition;
    m.joints = actual;
    m.marker = k;
    plan.push_back(m);
  }
  SimulationNoise noise;
  noise.position_m = options_.noise_m;
  noise.rotation_rad = options_.rotation_noise_rad;
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
      options_.drift_m_per_measurement * static_cast<double>(served_), 0, 0);
  for (const Measurement& m : measured) {
    // Every marker is simulated (the noise does not depend on which are
    // asked for); those not asked for, or not seen, are not reported.
    if (!asked(m.marker)) {
      reply->points_m.push_back(std::nullopt);
      if (options_.rotations) reply->rotations.push_back(std::nullopt);
      continue;
    }
    reply->points_m.push_back(m.position + drift);
    if (options_.rotations) reply->rotations.push_back(m.rotation);
  }
  if (options_.report_sigma && options_.noise_m > 0)
    reply->sigma_m = options_.noise_m;
}

}  // namespace activecal
