// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/driver/driver_client.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <utility>

namespace activecal {

namespace {

std::string SecondsText(double s) {
  std::ostringstream out;
  out << s;
  return out.str();
}

}  // namespace

bool DriverClientOptions::IsValid(std::string* error) const {
  if (driver.empty()) {
    *error = "driver must name a command or tcp://HOST:PORT";
    return false;
  }
  if (!(timeout_s > 0) || !std::isfinite(timeout_s)) {
    *error = "driver_timeout_s must be > 0, got " + SecondsText(timeout_s);
    return false;
  }
  return true;
}

DriverClient::DriverClient(DriverClientOptions options,
                           std::unique_ptr<DriverConnection> connection,
                           int num_joints, int num_markers)
    : options_(std::move(options)),
      connection_(std::move(connection)),
      name_(connection_->name()),
      num_joints_(num_joints),
      num_markers_(num_markers) {}

DriverClient::~DriverClient() { Close(); }

bool DriverClient::Start(const DriverClientOptions& options,
                         const DriverHello& hello,
                         std::unique_ptr<DriverClient>* client,
                         std::string* error) {
  if (!options.IsValid(error)) return false;
  std::unique_ptr<DriverConnection> connection;
  if (!OpenDriverConnection(options.driver, options.timeout_s, &connection,
                            error)) {
    return false;
  }
  std::unique_ptr<DriverClient> c(new DriverClient(
      options, std::move(connection),
      static_cast<int>(hello.joint_names.size()), hello.markers));
  std::string why;
  if (!c->connection_->channel().WriteLine(HelloMessage(hello), &why)) {
    *error = c->name_ + ": cannot send hello: " + why + " (the driver " +
             c->connection_->WhyClosed(1.0) + ")";
    c->broken_ = true;
    return false;
  }
  std::string line;
  if (!c->Read("its hello", &line, error)) return false;
  if (!ParseDriverHello(line, &why)) {
    *error = c->name_ + ": " + why;
    c->broken_ = true;
    return false;
  }
  c->driver_hello_ = line;
  *client = std::move(c);
  return true;
}

bool DriverClient::Read(const std::string& waiting_for, std::string* line,
                        std::string* error) {
  std::string why;
  // One deadline for the reply: blank lines do not restart it.
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    const double left =
        options_.timeout_s -
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    const LineChannel::ReadResult result =
        left > 0 ? connection_->channel().ReadLine(left, line, &why)
                 : LineChannel::ReadResult::kTimeout;
    switch (result) {
      case LineChannel::ReadResult::kLine:
        if (line->find_first_not_of(" \t") == std::string::npos) continue;
        return true;
      case LineChannel::ReadResult::kTimeout:
        *error = name_ + ": no reply within " +
                 SecondsText(options_.timeout_s) + " s while waiting for " +
                 waiting_for + " (driver_timeout_s)";
        break;
      case LineChannel::ReadResult::kClosed:
        *error = name_ + " " + connection_->WhyClosed(2.0) +
                 " while activecal waited for " + waiting_for;
        break;
      case LineChannel::ReadResult::kError:
        *error = name_ + ": " + why + " while waiting for " + waiting_for;
        break;
    }
    broken_ = true;
    return false;
  }
}

bool DriverClient::Measure(const Eigen::VectorXd& joints,
                           MeasurementReply* reply, std::string* error,
                           const std::vector<int>& markers) {
  if (broken_ || closed_) {
    *error = name_ + ": the conversation ended after an earlier failure";
    return false;
  }
  const int64_t id = next_id_++;
  const std::string what = "the reply to measure " + std::to_string(id);
  std::string why;
  if (!connection_->channel().WriteLine(MeasureMessage(id, joints, markers),
                                        &why)) {
    *error = name_ + ": cannot send measure " + std::to_string(id) + ": " +
             why + " (the driver " + connection_->WhyClosed(1.0) + ")";
    broken_ = true;
    return false;
  }
  std::string line;
  if (!Read(what, &line, error)) return false;
  if (!ParseMeasurementReply(line, id, num_joints_, num_markers_, reply,
                             &why)) {
    *error = name_ + ": " + what + ": " + why;
    broken_ = true;
    return false;
  }
  return true;
}

std::string DriverClient::Close() {
  if (closed_) return "";
  closed_ = true;
  std::string ignored;
  if (!broken_) connection_->channel().WriteLine(ByeMessage(), &ignored);
  return connection_->Shutdown(std::min(options_.timeout_s, 5.0));
}

}  // namespace activecal
