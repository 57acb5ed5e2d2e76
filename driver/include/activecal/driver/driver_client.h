// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal's side of the driver protocol (protocol.h) over a connection
// (connection.h): hello, then one measure request at a time, then bye.
//
//   DriverClientOptions options;
//   options.driver = "python3 examples/driver_example.py";
//   options.timeout_s = 60;
//   std::unique_ptr<DriverClient> driver;
//   if (!DriverClient::Start(options, hello, &driver, &error)) Fail(error);
//   MeasurementReply reply;
//   if (!driver->Measure(joints, &reply, &error)) Fail(error);
//   driver->Close();
//
// Every failure is one line naming the driver, the request and what came:
// no reply within the timeout, the driver exited (its status), a line that
// is not JSON, another id, the wrong joint or marker count, a NaN, an
// unknown status. After a failure the client is unusable (the conversation
// is out of step): close it; a session resumes with a new driver.

#ifndef ACTIVECAL_DRIVER_DRIVER_CLIENT_H_
#define ACTIVECAL_DRIVER_DRIVER_CLIENT_H_

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "activecal/driver/connection.h"
#include "activecal/driver/protocol.h"

namespace activecal {

struct DriverClientOptions {
  // A command ("python3 driver.py --robot=10.0.0.2", run without a shell)
  // or tcp://HOST:PORT.
  std::string driver;
  // The longest wait for any reply (s), > 0: the hello and every
  // measurement (a move, the settling and the tracker's reading). Blank
  // lines the driver writes meanwhile do not restart it.
  double timeout_s = 60.0;

  bool IsValid(std::string* error) const;
};

class DriverClient {
 public:
  ~DriverClient();  // Close()
  DriverClient(const DriverClient&) = delete;
  DriverClient& operator=(const DriverClient&) = delete;

  // Starts or connects to the driver and exchanges hellos.
  static bool Start(const DriverClientOptions& options,
                    const DriverHello& hello,
                    std::unique_ptr<DriverClient>* client, std::string* error);

  // Asks for a measurement at `joints` (rad, m) and checks the reply
  // (ParseMeasurementReply). Ids count from 1 per client.
  // `markers`: the markers to measure (MeasureMessage; empty: all).
  bool Measure(const Eigen::VectorXd& joints, MeasurementReply* reply,
               std::string* error, const std::vector<int>& markers = {});

  // Says bye and ends the connection (a child that does not exit within
  // the timeout is terminated). Idempotent. Returns a note if the driver
  // had to be terminated, else "".
  std::string Close();

  // The driver's hello line, as it came.
  const std::string& driver_hello() const { return driver_hello_; }
  const std::string& name() const { return name_; }
  // The id of the last measure request.
  int64_t last_id() const { return next_id_ - 1; }

 private:
  DriverClient(DriverClientOptions options,
               std::unique_ptr<DriverConnection> connection, int num_joints,
               int num_markers);
  // The next non-blank line, or false with "<name>: <what> while waiting
  // for <waiting_for>".
  bool Read(const std::string& waiting_for, std::string* line,
            std::string* error);

  DriverClientOptions options_;
  std::unique_ptr<DriverConnection> connection_;
  std::string name_;
  int num_joints_;
  int num_markers_;
  int64_t next_id_ = 1;
  bool broken_ = false;
  bool closed_ = false;
  std::string driver_hello_;
};

}  // namespace activecal

#endif  // ACTIVECAL_DRIVER_DRIVER_CLIENT_H_
