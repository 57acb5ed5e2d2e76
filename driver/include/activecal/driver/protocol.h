// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The driver protocol (docs/driver_protocol.md): how activecal hands a pose
// to a robot cell (a robot and a tracker behind a "driver" program) and
// gets the measurement back. One JSON object per line, in both directions:
//
//   activecal -> driver  {"type":"hello","protocol":1,"joint_names":[...],
//                         "markers":K,"robot":"..."}
//   driver -> activecal  {"type":"hello","protocol":1, ...anything}
//   activecal -> driver  {"type":"measure","id":N,"joints_rad":[...],
//                         optional "markers":[k, ...] (0-based: which to
//                         measure; absent: every marker)}
//   driver -> activecal  {"type":"measurement","id":N,"status":"ok",
//                         "joints_rad":[...encoder readings...],
//                         "points_m":[[x,y,z] or null per marker],
//                         optional "rotations":[[rx,ry,rz] or null per
//                         marker], optional "sigma_m":s}
//                     or {"type":"measurement","id":N,"status":
//                         "not_visible"|"unreachable"|"error","message":"..."}
//   activecal -> driver  {"type":"bye"}
//
// Units: joints in radians (revolute) and metres (prismatic: "joints_rad"
// holds metres for them), in activecal's joint convention (the robot
// file's or URDF's zero and sign); points in metres in the tracker's frame;
// rotations as rotation vectors (axis times angle, rad) of the marker's
// target frame in the tracker's frame; sigma_m the standard deviation per
// axis of every point of the reply (m).
//
// Both sides are here: activecal's (writing hello / measure / bye, reading
// the replies, every field checked and a bad one named) and the driver's
// (reading activecal's messages, writing replies), which the cell
// simulator activecal_sim_cell uses. The JSON library stays private.

#ifndef ACTIVECAL_DRIVER_PROTOCOL_H_
#define ACTIVECAL_DRIVER_PROTOCOL_H_

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"

namespace activecal {

inline constexpr int kDriverProtocolVersion = 1;

// What activecal says first.
struct DriverHello {
  int protocol = kDriverProtocolVersion;
  std::vector<std::string> joint_names;  // chain order
  int markers = 1;                       // points per measurement
  std::string robot;                     // the model's name
};

// The answer of a driver about one pose.
enum class MeasureStatus { kOk, kNotVisible, kUnreachable, kError };
// "ok", "not_visible", "unreachable", "error".
const char* MeasureStatusToString(MeasureStatus status);
bool StringToMeasureStatus(const std::string& text, MeasureStatus* status);

struct MeasurementReply {
  int64_t id = 0;
  MeasureStatus status = MeasureStatus::kOk;
  // kOk: the joints read at the pose (rad, m), one point per marker
  // (nullopt: not seen), optionally one rotation per marker (empty vector:
  // none sent; nullopt: none for that marker), sigma_m (0: not sent).
  Eigen::VectorXd joints;
  std::vector<std::optional<Eigen::Vector3d>> points_m;
  std::vector<std::optional<Eigen::Vector3d>> rotations;
  double sigma_m = 0.0;
  // Why a pose was not measured (any status; optional).
  std::string message;
};

// activecal's messages, one line each without the newline.
std::string HelloMessage(const DriverHello& hello);
// `markers` (0-based, ascending; empty: not sent, every marker) names the
// markers to measure, e.g. the cell's targets seen at the pose:
// "markers":[0,2].
std::string MeasureMessage(int64_t id, const Eigen::VectorXd& joints,
                           const std::vector<int>& markers = {});
std::string ByeMessage();

// Checks the driver's hello line: a JSON object of type "hello" and
// protocol kDriverProtocolVersion. The error names what came.
bool ParseDriverHello(const std::string& line, std::string* error);

// Checks a reply to measure `expected_id` of a robot with `num_joints`
// joints and `num_markers` markers: JSON, type "measurement", the id, a
// known status, and for "ok" joints_rad (num_joints finite numbers),
// points_m (num_markers entries, each null or three finite numbers),
// rotations (if sent: num_markers entries, null where the point is), a
// finite sigma_m > 0 (if sent). An "ok" reply that saw no marker is
// turned into "not_visible". The error names the field and what it held.
bool ParseMeasurementReply(const std::string& line, int64_t expected_id,
                           int num_joints, int num_markers,
                           MeasurementReply* reply, std::string* error);

// The measurements of an "ok" reply: one per marker seen (a position, or a
// pose with its rotation), the joints read, sigma_m on every axis.
std::vector<Measurement> ReplyMeasurements(const MeasurementReply& reply);

// The driver's side: activecal's messages read, replies written.
enum class ActivecalMessageType { kHello, kMeasure, kBye };
struct ActivecalMessage {
  ActivecalMessageType type = ActivecalMessageType::kHello;
  DriverHello hello;         // kHello
  int64_t id = 0;            // kMeasure
  Eigen::VectorXd joints;    // kMeasure (rad, m)
  std::vector<int> markers;  // kMeasure: the markers asked for (empty: all)
};
bool ParseActivecalMessage(const std::string& line, ActivecalMessage* message,
                           std::string* error);
// The driver's hello; `about` (may be empty) is a JSON object text whose
// members are added ("driver": "...", what the cell has; text that is not
// an object is added as "about").
std::string DriverHelloMessage(const std::string& about);
std::string MeasurementReplyMessage(const MeasurementReply& reply);

// The first `max_chars` characters of a line, for messages ("..." when
// cut).
std::string Excerpt(const std::string& line, size_t max_chars = 120);

}  // namespace activecal

#endif  // ACTIVECAL_DRIVER_PROTOCOL_H_
