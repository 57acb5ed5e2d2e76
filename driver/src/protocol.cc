// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/driver/protocol.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "activecal/core/enum_name_list.h"

namespace activecal {

using nlohmann::json;
// Messages are written with their members in the documented order ("type"
// first), read in any order.
using ordered = nlohmann::ordered_json;

namespace {

// The line parsed as one JSON object; the error says what came instead.
bool ParseObject(const std::string& line, json* out, std::string* error) {
  try {
    *out = json::parse(line);
  } catch (const json::parse_error& e) {
    std::string why = "not JSON";
    if (line.find("NaN") != std::string::npos ||
        line.find("Infinity") != std::string::npos) {
      why +=
          " (NaN and Infinity are not JSON numbers: send null for a marker "
          "not seen, and only finite values)";
    }
    *error = why + ": '" + Excerpt(line) + "'";
    return false;
  } catch (const json::out_of_range& e) {
    *error = "a number beyond the range of a double: '" + Excerpt(line) + "'";
    return false;
  }
  if (!out->is_object()) {
    *error = "not a JSON object: '" + Excerpt(line) + "'";
    return false;
  }
  return true;
}

std::string TypeOf(const json& j) {
  const auto it = j.find("type");
  if (it == j.end()) return "";
  return it->is_string() ? it->get<std::string>() : it->dump();
}

// A finite number, or false with "<field> is not a finite number (<it>)".
bool FiniteNumber(const json& j, const std::string& field, double* value,
                  std::string* error) {
  if (!j.is_number()) {
    *error = field + " is not a number: " + Excerpt(j.dump());
    return false;
  }
  *value = j.get<double>();
  if (!std::isfinite(*value)) {
    *error = field + " is not finite: " + Excerpt(j.dump());
    return false;
  }
  return true;
}

// An array of `n` finite numbers.
bool NumberArray(const json& j, const std::string& field, int n,
                 const std::string& count_of, Eigen::VectorXd* out,
                 std::string* error) {
  if (!j.is_array()) {
    *error = field + " is not an array: " + Excerpt(j.dump());
    return false;
  }
  if (static_cast<int>(j.size()) != n) {
    *error =
        field + " has " + std::to_string(j.size()) + " values, " + count_of;
    return false;
  }
  out->resize(n);
  for (int i = 0; i < n; ++i) {
    if (!FiniteNumber(j[i], field + "[" + std::to_string(i) + "]", &(*out)[i],
                      error)) {
      return false;
    }
  }
  return true;
}

// An array of `n` entries, each null or three finite numbers.
bool OptionalTriples(const json& j, const std::string& field, int n,
                     std::vector<std::optional<Eigen::Vector3d>>* out,
                     std::string* error) {
  if (!j.is_array()) {
    *error = field + " is not an array: " + Excerpt(j.dump());
    return false;
  }
  if (static_cast<int>(j.size()) != n) {
    *error = field + " has " + std::to_string(j.size()) +
             " entries, one per marker expected (" + std::to_string(n) +
             "; null for a marker not seen)";
    return false;
  }
  out->assign(n, std::nullopt);
  for (int k = 0; k < n; ++k) {
    if (j[k].is_null()) continue;
    Eigen::VectorXd v;
    if (!NumberArray(j[k], field + "[" + std::to_string(k) + "]", 3,
                     "expected [x, y, z] or null", &v, error)) {
      return false;
    }
    (*out)[k] = Eigen::Vector3d(v[0], v[1], v[2]);
  }
  return true;
}

ordered Vector(const Eigen::VectorXd& v) {
  ordered a = ordered::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v[i]);
  return a;
}

}  // namespace

constexpr const char* kMeasureStatusNames[] = {"ok", "not_visible",
                                               "unreachable", "error"};
ACTIVECAL_ENUM_STRING_FUNCTIONS(MeasureStatus, kMeasureStatusNames)

std::string Excerpt(const std::string& line, size_t max_chars) {
  std::string out;
  for (char c : line) {
    if (out.size() >= max_chars) return out + "...";
    // Control characters (a binary answer) stay visible and on one line.
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      static const char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[(c >> 4) & 0xf];
      out += kHex[c & 0xf];
    } else {
      out += c;
    }
  }
  return out;
}

std::string HelloMessage(const DriverHello& hello) {
  ordered j = {{"type", "hello"},
               {"protocol", hello.protocol},
               {"joint_names", hello.joint_names},
               {"markers", hello.markers},
               {"robot", hello.robot}};
  return j.dump();
}

std::string MeasureMessage(int64_t id, const Eigen::VectorXd& joints,
                           const std::vector<int>& markers) {
  ordered j = {{"type", "measure"}, {"id", id}, {"joints_rad", Vector(joints)}};
  if (!markers.empty()) j["markers"] = markers;
  return j.dump();
}

std::string ByeMessage() { return ordered{{"type", "bye"}}.dump(); }

bool ParseDriverHello(const std::string& line, std::string* error) {
  json j;
  if (!ParseObject(line, &j, error)) return false;
  if (TypeOf(j) != "hello") {
    *error = "expected the driver's hello, got a message of type '" +
             TypeOf(j) + "': '" + Excerpt(line) + "'";
    return false;
  }
  const auto p = j.find("protocol");
  if (p == j.end() || !p->is_number_integer()) {
    *error = "the driver's hello has no integer \"protocol\": '" +
             Excerpt(line) + "'";
    return false;
  }
  if (p->get<int64_t>() != kDriverProtocolVersion) {
    *error = "the driver speaks protocol " + p->dump() + ", activecal " +
             std::to_string(kDriverProtocolVersion);
    return false;
  }
  return true;
}

bool ParseMeasurementReply(const std::string& line, int64_t expected_id,
                           int num_joints, int num_markers,
                           MeasurementReply* reply, std::string* error) {
  *reply = MeasurementReply();
  json j;
  if (!ParseObject(line, &j, error)) return false;
  if (TypeOf(j) != "measurement") {
    *error = "expected a message of type 'measurement', got '" + TypeOf(j) +
             "': '" + Excerpt(line) + "'";
    return false;
  }
  const auto id = j.find("id");
  if (id == j.end() || !id->is_number_integer()) {
    *error = "no integer \"id\": '" + Excerpt(line) + "'";
    return false;
  }
  if (id->get<int64_t>() != expected_id) {
    *error = "id " + id->dump() + ", expected " + std::to_string(expected_id) +
             " (the reply to another request)";
    return false;
  }
  reply->id = expected_id;
  const auto status = j.find("status");
  if (status == j.end() || !status->is_string()) {
    *error = "no \"status\" (ok, not_visible, unreachable or error): '" +
             Excerpt(line) + "'";
    return false;
  }
  if (!StringToMeasureStatus(status->get<std::string>(), &reply->status)) {
    *error = "status '" + Excerpt(status->get<std::string>()) +
             "' is not ok, not_visible, unreachable or error";
    return false;
  }
  const auto message = j.find("message");
  if (message != j.end()) {
    reply->message =
        message->is_string() ? message->get<std::string>() : message->dump();
  }
  if (reply->status != MeasureStatus::kOk) return true;

  const auto joints = j.find("joints_rad");
  if (joints == j.end()) {
    *error = "status ok without \"joints_rad\" (the joints read at the pose)";
    return false;
  }
  if (!NumberArray(*joints, "joints_rad", num_joints,
                   "the robot has " + std::to_string(num_joints) + " joints",
                   &reply->joints, error)) {
    return false;
  }
  const auto points = j.find("points_m");
  if (points == j.end()) {
    *error = "status ok without \"points_m\"";
    return false;
  }
  if (!OptionalTriples(*points, "points_m", num_markers, &reply->points_m,
                       error)) {
    return false;
  }
  const auto rotations = j.find("rotations");
  if (rotations != j.end() && !rotations->is_null()) {
    if (!OptionalTriples(*rotations, "rotations", num_markers,
                         &reply->rotations, error)) {
      return false;
    }
    for (int k = 0; k < num_markers; ++k) {
      if (reply->rotations[k] && !reply->points_m[k]) {
        *error = "rotations[" + std::to_string(k) +
                 "] is given for a marker whose point is null";
        return false;
      }
    }
  }
  const auto sigma = j.find("sigma_m");
  if (sigma != j.end() && !sigma->is_null()) {
    if (!FiniteNumber(*sigma, "sigma_m", &reply->sigma_m, error)) return false;
    if (!(reply->sigma_m > 0)) {
      *error = "sigma_m must be > 0, got " + sigma->dump();
      return false;
    }
  }
  bool seen = false;
  for (const auto& p : reply->points_m) seen |= p.has_value();
  if (!seen) {
    reply->status = MeasureStatus::kNotVisible;
    if (reply->message.empty()) {
      reply->message = "status ok, but no marker seen (every point null)";
    }
  }
  return true;
}

std::vector<Measurement> ReplyMeasurements(const MeasurementReply& reply) {
  std::vector<Measurement> out;
  if (reply.status != MeasureStatus::kOk) return out;
  for (size_t k = 0; k < reply.points_m.size(); ++k) {
    if (!reply.points_m[k]) continue;
    Measurement m;
    m.joints = reply.joints;
    m.position = *reply.points_m[k];
    m.marker = static_cast<int>(k);
    if (k < reply.rotations.size() && reply.rotations[k]) {
      m.type = MeasurementType::kPose;
      m.rotation = *reply.rotations[k];
    }
    if (reply.sigma_m > 0) m.sigma_m.setConstant(reply.sigma_m);
    out.push_back(m);
  }
  return out;
}

bool ParseActivecalMessage(const std::string& line, ActivecalMessage* message,
                           std::string* error) {
  *message = ActivecalMessage();
  json j;
  if (!ParseObject(line, &j, error)) return false;
  const std::string type = TypeOf(j);
  if (type == "bye") {
    message->type = ActivecalMessageType::kBye;
    return true;
  }
  if (type == "hello") {
    message->type = ActivecalMessageType::kHello;
    try {
      message->hello.protocol = j.at("protocol").get<int>();
      message->hello.joint_names =
          j.at("joint_names").get<std::vector<std::string>>();
      message->hello.markers = j.at("markers").get<int>();
      if (j.contains("robot") && j["robot"].is_string()) {
        message->hello.robot = j["robot"].get<std::string>();
      }
    } catch (const json::exception& e) {
      *error = "hello: " + std::string(e.what());
      return false;
    }
    return true;
  }
  if (type == "measure") {
    message->type = ActivecalMessageType::kMeasure;
    const auto id = j.find("id");
    if (id == j.end() || !id->is_number_integer()) {
      *error = "measure without an integer id";
      return false;
    }
    message->id = id->get<int64_t>();
    const auto joints = j.find("joints_rad");
    if (joints == j.end() || !joints->is_array()) {
      *error = "measure without joints_rad";
      return false;
    }
    if (!NumberArray(*joints, "joints_rad", static_cast<int>(joints->size()),
                     "", &message->joints, error)) {
      return false;
    }
    message->markers.clear();
    const auto markers = j.find("markers");
    if (markers != j.end()) {
      if (!markers->is_array()) {
        *error = "measure: markers: expected an array of marker indices";
        return false;
      }
      for (const auto& k : *markers) {
        if (!k.is_number_integer() || k.get<int64_t>() < 0 ||
            k.get<int64_t>() > 1 << 20) {
          *error =
              "measure: markers: expected marker indices >= 0, got " + k.dump();
          return false;
        }
        message->markers.push_back(static_cast<int>(k.get<int64_t>()));
      }
    }
    return true;
  }
  *error = "unknown message type '" + type + "'";
  return false;
}

std::string DriverHelloMessage(const std::string& about) {
  ordered j = {{"type", "hello"}, {"protocol", kDriverProtocolVersion}};
  if (!about.empty()) {
    const ordered extra = ordered::parse(about, nullptr, false);
    if (extra.is_object()) {
      for (const auto& item : extra.items()) {
        if (item.key() != "type" && item.key() != "protocol") {
          j[item.key()] = item.value();
        }
      }
    } else {
      j["about"] = about;
    }
  }
  return j.dump();
}

std::string MeasurementReplyMessage(const MeasurementReply& reply) {
  ordered j = {{"type", "measurement"},
               {"id", reply.id},
               {"status", MeasureStatusToString(reply.status)}};
  if (!reply.message.empty()) j["message"] = reply.message;
  if (reply.status != MeasureStatus::kOk) return j.dump();
  j["joints_rad"] = Vector(reply.joints);
  auto triples = [](const std::vector<std::optional<Eigen::Vector3d>>& v) {
    ordered a = ordered::array();
    for (const auto& p : v) a.push_back(p ? Vector(*p) : ordered());
    return a;
  };
  j["points_m"] = triples(reply.points_m);
  if (!reply.rotations.empty()) j["rotations"] = triples(reply.rotations);
  if (reply.sigma_m > 0) j["sigma_m"] = reply.sigma_m;
  return j.dump();
}

}  // namespace activecal
