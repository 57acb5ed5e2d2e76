// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The driver protocol: every bad reply named, messages read back exactly,
// commands split without a shell, the client against real processes (a
// driver that exits, hangs, answers garbage or another protocol) and over
// TCP; and the controller programs, parsed back, in the controller's joint
// convention (the shipped iiwa file checked against the URDF's axes).

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <regex>
#include <string>
#include <thread>

#include "activecal/core/measurement.h"
#include "activecal/core/puma560.h"
#include "activecal/driver/connection.h"
#include "activecal/driver/driver_client.h"
#include "activecal/driver/protocol.h"
#include "activecal/driver/simulated_cell.h"
#include "activecal/io/controller_programs.h"
#include "activecal/io/robot_loader.h"

namespace activecal {
namespace {

const char kOk[] =
    R"({"type":"measurement","id":7,"status":"ok","joints_rad":[0.1,-0.2],)"
    R"("points_m":[[1,2,3],null]})";

TEST(DriverProtocolTest, AGoodReplyIsReadExactly) {
  MeasurementReply reply;
  std::string error;
  ASSERT_TRUE(ParseMeasurementReply(kOk, 7, 2, 2, &reply, &error)) << error;
  EXPECT_EQ(reply.status, MeasureStatus::kOk);
  EXPECT_EQ(reply.joints, Eigen::Vector2d(0.1, -0.2));
  ASSERT_EQ(reply.points_m.size(), 2u);
  EXPECT_EQ(*reply.points_m[0], Eigen::Vector3d(1, 2, 3));
  EXPECT_FALSE(reply.points_m[1].has_value());
  const std::vector<Measurement> m = ReplyMeasurements(reply);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].marker, 0);
  EXPECT_EQ(m[0].type, MeasurementType::kPosition);

  // Written by the driver side and read back: the same doubles.
  MeasurementReply out;
  out.id = 3;
  out.joints = Eigen::Vector2d(1.0 / 3.0, -2e-300);
  out.points_m = {Eigen::Vector3d(0.1, 1e10, -M_PI), std::nullopt};
  out.rotations = {Eigen::Vector3d(0.3, 0.2, 0.1), std::nullopt};
  out.sigma_m = 2.5e-5;
  ASSERT_TRUE(ParseMeasurementReply(MeasurementReplyMessage(out), 3, 2, 2,
                                    &reply, &error))
      << error;
  EXPECT_EQ(reply.joints, out.joints);
  EXPECT_EQ(*reply.points_m[0], *out.points_m[0]);
  EXPECT_EQ(*reply.rotations[0], *out.rotations[0]);
  EXPECT_EQ(reply.sigma_m, out.sigma_m);
  const std::vector<Measurement> pose = ReplyMeasurements(reply);
  ASSERT_EQ(pose.size(), 1u);
  EXPECT_EQ(pose[0].type, MeasurementType::kPose);
  EXPECT_EQ(pose[0].sigma_m, Eigen::Vector3d::Constant(2.5e-5));

  // Activecal's measure request, as the driver reads it.
  ActivecalMessage m2;
  ASSERT_TRUE(ParseActivecalMessage(MeasureMessage(9, out.joints), &m2, &error))
      << error;
  EXPECT_EQ(m2.type, ActivecalMessageType::kMeasure);
  EXPECT_EQ(m2.id, 9);
  EXPECT_EQ(m2.joints, out.joints);

  // ok without any marker seen is not_visible.
  ASSERT_TRUE(ParseMeasurementReply(
      R"({"type":"measurement","id":1,"status":"ok","joints_rad":[0,0],"points_m":[null]})",
      1, 2, 1, &reply, &error));
  EXPECT_EQ(reply.status, MeasureStatus::kNotVisible);
  EXPECT_TRUE(ReplyMeasurements(reply).empty());
  // The other statuses need nothing else.
  ASSERT_TRUE(ParseMeasurementReply(
      R"({"type":"measurement","id":1,"status":"unreachable","message":"fence"})",
      1, 2, 1, &reply, &error));
  EXPECT_EQ(reply.status, MeasureStatus::kUnreachable);
  EXPECT_EQ(reply.message, "fence");
}

TEST(DriverProtocolTest, EveryBadReplyIsNamed) {
  const std::string head = R"({"type":"measurement","id":7,)";
  const struct {
    std::string line;
    std::string named;
  } cases[] = {
      {"moving to pose 7", "not JSON: 'moving to pose 7'"},
      {head + R"("status":"ok","joints_rad":[0,0],"points_m":[[NaN,1,2]]})",
       "NaN and Infinity are not JSON numbers"},
      {"[1,2]", "not a JSON object"},
      {R"({"type":"hello","protocol":1})",
       "expected a message of type 'measurement', got 'hello'"},
      {R"({"type":"measurement","id":8,"status":"ok"})", "id 8, expected 7"},
      {R"({"type":"measurement","status":"ok"})", "no integer \"id\""},
      {head + R"("status":"done"})",
       "status 'done' is not ok, not_visible, unreachable or error"},
      {head + R"("joints_rad":[0,0]})", "no \"status\""},
      {head + R"("status":"ok","points_m":[[1,2,3]]})",
       "without \"joints_rad\""},
      {head + R"("status":"ok","joints_rad":[0,0,0],"points_m":[[1,2,3]]})",
       "joints_rad has 3 values, the robot has 2 joints"},
      {head + R"("status":"ok","joints_rad":[0,null],"points_m":[[1,2,3]]})",
       "joints_rad[1] is not a number"},
      {head + R"("status":"ok","joints_rad":[0,1e400],"points_m":[[1,2,3]]})",
       "a number beyond the range of a double"},
      {head + R"("status":"ok","joints_rad":[0,0]})", "without \"points_m\""},
      {head +
           R"("status":"ok","joints_rad":[0,0],"points_m":[[1,2,3],[1,2,3]]})",
       "points_m has 2 entries, one per marker expected (1"},
      {head + R"("status":"ok","joints_rad":[0,0],"points_m":[[1,2]]})",
       "points_m[0] has 2 values, expected [x, y, z] or null"},
      {head + R"("status":"ok","joints_rad":[0,0],"points_m":[null],)"
              R"("rotations":[[0,0,1]]})",
       "rotations[0] is given for a marker whose point is null"},
      {head + R"("status":"ok","joints_rad":[0,0],"points_m":[[1,2,3]],)"
              R"("sigma_m":0})",
       "sigma_m must be > 0"},
  };
  for (const auto& c : cases) {
    MeasurementReply reply;
    std::string error;
    EXPECT_FALSE(ParseMeasurementReply(c.line, 7, 2, 1, &reply, &error))
        << c.line;
    EXPECT_NE(error.find(c.named), std::string::npos)
        << "line: " << c.line << "\nerror: " << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
  std::string error;
  EXPECT_FALSE(ParseDriverHello(R"({"type":"hello","protocol":2})", &error));
  EXPECT_NE(error.find("the driver speaks protocol 2, activecal 1"),
            std::string::npos)
      << error;
  EXPECT_FALSE(ParseDriverHello(R"({"type":"hello"})", &error));
  EXPECT_NE(error.find("no integer \"protocol\""), std::string::npos);
  // A binary answer stays on one line.
  EXPECT_EQ(Excerpt(std::string("a\nb\x01", 4)), "a\\x0ab\\x01");
}

TEST(DriverConnectionTest, CommandsAreSplitWithoutAShell) {
  std::vector<std::string> words;
  std::string error;
  ASSERT_TRUE(SplitDriverCommand(
      "python3 'my driver.py' --port=\"/dev/tty USB0\" a\\ b", &words, &error))
      << error;
  EXPECT_EQ(words, (std::vector<std::string>{"python3", "my driver.py",
                                             "--port=/dev/tty USB0", "a b"}));
  EXPECT_FALSE(SplitDriverCommand("driver | tee log", &words, &error));
  EXPECT_NE(error.find("runs the command without a shell"), std::string::npos)
      << error;
  EXPECT_FALSE(SplitDriverCommand("driver $(rm -rf x)", &words, &error));
  EXPECT_NE(error.find("command substitution"), std::string::npos) << error;
  EXPECT_FALSE(SplitDriverCommand("driver 'open", &words, &error));
  EXPECT_NE(error.find("unbalanced quotes"), std::string::npos) << error;
  EXPECT_FALSE(SplitDriverCommand("   ", &words, &error));
}

DriverHello TwoJoints() {
  DriverHello hello;
  hello.joint_names = {"j1", "j2"};
  hello.markers = 1;
  hello.robot = "test";
  return hello;
}

// A driver written in sh: reads activecal's hello, then runs `body`.
std::string ShDriver(const std::string& body) {
  return "sh -c 'read line; " + body + "'";
}

const char kHelloReply[] = R"(echo "{\"type\":\"hello\",\"protocol\":1}")";

TEST(DriverClientTest, AConversationWithAChildProcess) {
  DriverClientOptions options;
  options.timeout_s = 5;
  options.driver = ShDriver(
      std::string(kHelloReply) +
      R"(; read line; echo "{\"type\":\"measurement\",\"id\":1,\"status\":)"
      R"(\"ok\",\"joints_rad\":[0.5,0.25],\"points_m\":[[1,2,3]]}"; )"
      R"(read line; echo "{\"type\":\"measurement\",\"id\":2,\"status\":)"
      R"(\"not_visible\",\"message\":\"behind the column\"}"; read line)");
  std::unique_ptr<DriverClient> client;
  std::string error;
  ASSERT_TRUE(DriverClient::Start(options, TwoJoints(), &client, &error))
      << error;
  EXPECT_EQ(client->driver_hello(), R"({"type":"hello","protocol":1})");
  MeasurementReply reply;
  ASSERT_TRUE(client->Measure(Eigen::Vector2d(0.5, 0.2), &reply, &error))
      << error;
  EXPECT_EQ(reply.joints, Eigen::Vector2d(0.5, 0.25));  // read, not commanded
  ASSERT_TRUE(client->Measure(Eigen::Vector2d(0, 0), &reply, &error)) << error;
  EXPECT_EQ(reply.status, MeasureStatus::kNotVisible);
  EXPECT_EQ(reply.message, "behind the column");
  EXPECT_EQ(client->Close(), "");
}

TEST(DriverClientTest, EveryFailureIsOneLineNamingTheDriver) {
  DriverClientOptions options;
  options.timeout_s = 0.3;
  struct Case {
    std::string driver;
    bool at_start;
    std::string named;
  };
  const Case cases[] = {
      // Whether the driver is gone before activecal sends its hello
      // ("cannot send hello: Broken pipe (the driver exited with status
      // 3)") or after ("exited with status 3 while activecal waited for its
      // hello") is a race the machine's load decides: both name the status.
      {"sh -c 'exit 3'", true, "exited with status 3"},
      {"no-such-driver-program --x", true,
       "cannot start 'no-such-driver-program': No such file or directory"},
      {ShDriver(R"(echo "{\"type\":\"hello\",\"protocol\":2}"; read line)"),
       true, "the driver speaks protocol 2"},
      {ShDriver("exec sleep 10"), true,
       "no reply within 0.3 s while waiting for its hello"},
      {ShDriver(std::string(kHelloReply) + "; read line; echo ready"), false,
       "the reply to measure 1: not JSON: 'ready'"},
      {ShDriver(std::string(kHelloReply) + "; read line; kill -9 $$"), false,
       "was killed by signal 9"},
      {ShDriver(std::string(kHelloReply) + "; read line; exec sleep 10"), false,
       "no reply within 0.3 s while waiting for the reply to measure 1"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.driver);
    options.driver = c.driver;
    std::unique_ptr<DriverClient> client;
    std::string error;
    const bool started =
        DriverClient::Start(options, TwoJoints(), &client, &error);
    if (c.at_start) {
      EXPECT_FALSE(started);
    } else {
      ASSERT_TRUE(started) << error;
      MeasurementReply reply;
      EXPECT_FALSE(client->Measure(Eigen::Vector2d(0, 0), &reply, &error));
      // After a failure the conversation is over.
      std::string again;
      EXPECT_FALSE(client->Measure(Eigen::Vector2d(0, 0), &reply, &again));
      EXPECT_NE(again.find("ended after an earlier failure"),
                std::string::npos);
    }
    EXPECT_NE(error.find(c.named), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
}

TEST(DriverClientTest, ADriverOverTcp) {
  std::unique_ptr<TcpListener> listener;
  std::string error;
  ASSERT_TRUE(TcpListener::Listen("127.0.0.1", 0, &listener, &error)) << error;
  ASSERT_GT(listener->port(), 0);
  std::string got_hello, got_bye;
  std::thread driver([&] {
    std::unique_ptr<LineChannel> channel;
    std::string e, line;
    if (!listener->Accept(&channel, &e)) return;
    channel->ReadLine(5, &got_hello, &e);
    channel->WriteLine(DriverHelloMessage(R"({"driver":"test"})"), &e);
    channel->ReadLine(5, &line, &e);
    ActivecalMessage m;
    ParseActivecalMessage(line, &m, &e);
    MeasurementReply r;
    r.id = m.id;
    r.joints = m.joints;
    r.points_m = {Eigen::Vector3d(0.5, 0.5, 0.5)};
    channel->WriteLine(MeasurementReplyMessage(r), &e);
    channel->ReadLine(5, &got_bye, &e);
  });
  DriverClientOptions options;
  options.driver = "tcp://127.0.0.1:" + std::to_string(listener->port());
  options.timeout_s = 5;
  std::unique_ptr<DriverClient> client;
  ASSERT_TRUE(DriverClient::Start(options, TwoJoints(), &client, &error))
      << error;
  MeasurementReply reply;
  ASSERT_TRUE(client->Measure(Eigen::Vector2d(0.125, 0.5), &reply, &error))
      << error;
  EXPECT_EQ(reply.joints, Eigen::Vector2d(0.125, 0.5));
  client->Close();
  driver.join();
  EXPECT_NE(got_hello.find("\"joint_names\":[\"j1\",\"j2\"]"),
            std::string::npos)
      << got_hello;
  EXPECT_EQ(got_bye, R"({"type":"bye"})");

  const int port = listener->port();
  listener.reset();
  options.driver = "tcp://127.0.0.1:" + std::to_string(port);
  EXPECT_FALSE(DriverClient::Start(options, TwoJoints(), &client, &error));
  EXPECT_NE(error.find("cannot connect to tcp://127.0.0.1:"), std::string::npos)
      << error;
  options.driver = "tcp://nohost";
  EXPECT_FALSE(DriverClient::Start(options, TwoJoints(), &client, &error));
  EXPECT_NE(error.find("is not tcp://HOST:PORT"), std::string::npos) << error;
  for (const char* bad : {"tcp://127.0.0.1:0", "tcp://127.0.0.1:70000",
                          "tcp://127.0.0.1:99999999999"}) {
    options.driver = bad;
    EXPECT_FALSE(DriverClient::Start(options, TwoJoints(), &client, &error));
    EXPECT_NE(error.find("the port must be in 1..65535"), std::string::npos)
        << error;
  }
}

// Writing to a driver that has gone is an error, never a SIGPIPE, and the
// process's own disposition of SIGPIPE is left as it was: activecal_active
// piped into `head` still ends when head does, instead of driving the
// robot on with nobody reading.
TEST(DriverConnectionTest, ADriverThatHasGoneIsAnErrorAndSigpipeIsUntouched) {
  struct sigaction saved {};
  sigaction(SIGPIPE, nullptr, &saved);
  signal(SIGPIPE, SIG_DFL);
  std::unique_ptr<DriverConnection> connection;
  std::string error, line;
  ASSERT_TRUE(OpenDriverConnection("true", 5, &connection, &error)) << error;
  // The child has exited once its stdout is closed.
  ASSERT_EQ(connection->channel().ReadLine(5, &line, &error),
            LineChannel::ReadResult::kClosed);
  EXPECT_FALSE(
      connection->channel().WriteLine(std::string(1 << 17, 'x'), &error));
  EXPECT_EQ(error, "Broken pipe");
  struct sigaction now {};
  sigaction(SIGPIPE, nullptr, &now);
  EXPECT_EQ(now.sa_handler, SIG_DFL);
  sigset_t pending;
  sigpending(&pending);
  EXPECT_FALSE(sigismember(&pending, SIGPIPE));
  EXPECT_EQ(connection->WhyClosed(5), "exited with status 0");
  sigaction(SIGPIPE, &saved, nullptr);
}

// Starts the sh driver that answers the hello and then runs `after_hello`,
// and asks it for one measurement; returns the error of that request
// ("" if it succeeded). The client is kept for Close().
std::string FirstMeasureError(const std::string& after_hello, double timeout_s,
                              std::unique_ptr<DriverClient>* client) {
  DriverClientOptions options;
  options.timeout_s = timeout_s;
  options.driver =
      ShDriver(std::string(kHelloReply) + "; read line; " + after_hello);
  std::string error;
  if (!DriverClient::Start(options, TwoJoints(), client, &error)) {
    return "start: " + error;
  }
  MeasurementReply reply;
  return (*client)->Measure(Eigen::Vector2d(0, 0), &reply, &error) ? "" : error;
}

// A driver that floods its stdout after a failure is not waited for: its
// pipe is closed, so it ends at once rather than being terminated after
// the wait.
TEST(DriverClientTest, AFloodingDriverEndsWhenTheClientCloses) {
  std::unique_ptr<DriverClient> client;
  const std::string error = FirstMeasureError("exec yes flood", 5, &client);
  EXPECT_NE(error.find("not JSON: 'flood'"), std::string::npos) << error;
  ASSERT_NE(client, nullptr);
  EXPECT_EQ(client->Close(), "");
}

// Blank lines are not a reply: they do not restart the timeout.
TEST(DriverClientTest, BlankLinesDoNotExtendTheTimeout) {
  std::unique_ptr<DriverClient> client;
  const std::string error = FirstMeasureError(
      "for i in 1 2 3 4 5 6 7 8 9 10; do echo; sleep 0.1; done; "
      R"(echo "{\"type\":\"measurement\",\"id\":1,\"status\":)"
      R"(\"not_visible\"}"; read line)",
      0.4, &client);
  EXPECT_NE(error.find("no reply within 0.4 s"), std::string::npos) << error;
}

// A driver that stops reading (closes its stdin) and exits is named when
// the request cannot be sent, with its exit status.
TEST(DriverClientTest, ADriverThatStopsReadingIsNamed) {
  DriverClientOptions options;
  options.timeout_s = 5;
  options.driver = ShDriver("exec 0<&-; " + std::string(kHelloReply));
  std::unique_ptr<DriverClient> client;
  std::string error;
  ASSERT_TRUE(DriverClient::Start(options, TwoJoints(), &client, &error))
      << error;
  MeasurementReply reply;
  EXPECT_FALSE(client->Measure(Eigen::Vector2d(0, 0), &reply, &error));
  EXPECT_NE(error.find("cannot send measure 1: Broken pipe (the driver "
                       "exited with status 0)"),
            std::string::npos)
      << error;
}

// --- Controller programs ---

std::vector<std::vector<double>> NumbersIn(const std::string& text,
                                           const std::regex& line) {
  std::vector<std::vector<double>> rows;
  const std::regex number(R"(-?[0-9]+(\.[0-9]+)?(E9)?)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), line);
       it != std::sregex_iterator(); ++it) {
    const std::string inside = (*it)[1];
    std::vector<double> row;
    for (auto n = std::sregex_iterator(inside.begin(), inside.end(), number);
         n != std::sregex_iterator(); ++n) {
      row.push_back(std::stod(n->str()));
    }
    rows.push_back(row);
  }
  return rows;
}

// The joint values of each move of a program, in the program's units:
// KRL's axis names and RAPID's unused external axes (9E9, checked)
// dropped, `num_joints` per move.
std::vector<std::vector<double>> MovesIn(const std::string& text,
                                         ProgramLanguage language,
                                         int num_joints) {
  const std::regex move(
      language == ProgramLanguage::kUrScript ? R"(movej\(\[([^\]]*)\])"
      : language == ProgramLanguage::kKrl    ? R"(PTP \{([^}]*)\})"
                                             : R"(MoveAbsJ \[\[(.*)\]\],)");
  std::vector<std::vector<double>> rows = NumbersIn(text, move);
  for (std::vector<double>& row : rows) {
    if (language == ProgramLanguage::kKrl) {
      // "A1 v, ..., E1 v": every other number is an axis number.
      std::vector<double> values;
      for (size_t k = 1; k < row.size(); k += 2) values.push_back(row[k]);
      row = values;
    }
    if (language == ProgramLanguage::kRapid) {
      EXPECT_EQ(row.size(), 12u);
      for (size_t k = num_joints; k < row.size(); ++k) {
        EXPECT_EQ(row[k], 9e9);
      }
      row.resize(std::min<size_t>(row.size(), num_joints));
    }
    EXPECT_EQ(row.size(), static_cast<size_t>(num_joints));
  }
  return rows;
}

// The program ControllerProgramText writes for the poses (in *text) and its
// moves (MovesIn, in *rows); a failure with its error where it writes none.
::testing::AssertionResult ProgramMoves(
    const RobotModel& model, const ControllerConvention& convention,
    const PoseList& poses, const ControllerProgramOptions& options,
    std::string* text, std::vector<std::vector<double>>* rows) {
  std::string error;
  if (!ControllerProgramText(model, convention, poses, options, text, &error)) {
    return ::testing::AssertionFailure() << error;
  }
  *rows = MovesIn(*text, options.language, model.num_joints());
  return ::testing::AssertionSuccess();
}

// Program units per rad (a revolute joint).
double UnitPerRad(ProgramLanguage language) {
  return language == ProgramLanguage::kUrScript ? 1.0 : 180 / M_PI;
}

RobotModel Iiwa() {
  RobotDescription robot;
  std::string error;
  EXPECT_TRUE(LoadRobot(ACTIVECAL_DATA_DIR "/kuka_iiwa14.urdf",
                        RobotLoadOptions(), &robot, &error))
      << error;
  return robot.model;
}

// The shipped data/controllers/kuka_iiwa14.yaml.
ControllerConvention IiwaConvention(const RobotModel& model) {
  ControllerConvention convention;
  std::string error;
  EXPECT_TRUE(ReadControllerConvention(ACTIVECAL_DATA_DIR
                                       "/controllers/kuka_iiwa14.yaml",
                                       model, &convention, &error))
      << error;
  return convention;
}

TEST(ControllerProgramTest, TheProgramsHoldThePosesInTheControllersConvention) {
  const RobotModel model = Iiwa();
  ControllerConvention convention = IiwaConvention(model);
  std::string error;
  // An offset too, to see the zero applied.
  convention.joints[2].offset = 10 * M_PI / 180;
  PoseList poses;
  poses.joints.resize(3, 7);
  poses.joints << 0.1, -0.2, 0.3, -1.5, 2.9, -2.0, 3.0,  //
      0, 0, 0, 0, 0, 0, 0,                               //
      -2.9, 2.0, -0.7, 1.1, -0.01, 0.5, -3.05;
  poses.pose_indices = {17, 3, 250};
  ControllerProgramOptions options;
  options.wait_s = 1.5;
  for (ProgramLanguage language :
       {ProgramLanguage::kUrScript, ProgramLanguage::kKrl,
        ProgramLanguage::kRapid}) {
    SCOPED_TRACE(ProgramLanguageToString(language));
    options.language = language;
    const double unit = UnitPerRad(language);
    const double digits = language == ProgramLanguage::kUrScript ? 1e-9 : 1e-6;
    std::string text;
    std::vector<std::vector<double>> rows;
    ASSERT_TRUE(ProgramMoves(model, convention, poses, options, &text, &rows));
    ASSERT_EQ(rows.size(), 3u) << text;
    for (int i = 0; i < 3; ++i) {
      ASSERT_EQ(rows[i].size(), 7u);
      for (int j = 0; j < 7; ++j) {
        const ControllerJoint& c = convention.joints[j];
        const double want = (c.sign * poses.joints(i, j) + c.offset) * unit;
        EXPECT_NEAR(rows[i][j], want, 0.51 * digits)
            << "pose " << i << " joint " << j;
      }
    }
    // The waits, one per pose, and the pose indices in comments.
    const std::regex wait(
        language == ProgramLanguage::kUrScript ? R"(sleep\(1\.500\))"
        : language == ProgramLanguage::kKrl    ? R"(WAIT SEC 1\.500)"
                                               : R"(WaitTime 1\.500;)");
    EXPECT_EQ(
        std::distance(std::sregex_iterator(text.begin(), text.end(), wait),
                      std::sregex_iterator()),
        3);
    EXPECT_NE(text.find("pose 3 of 3: pose_index 250"), std::string::npos);
  }
  // Zero is written without a sign.
  options.language = ProgramLanguage::kKrl;
  std::string text;
  ASSERT_TRUE(
      ControllerProgramText(model, convention, poses, options, &text, &error));
  EXPECT_NE(text.find("PTP {A1 0.000000, A2 0.000000"), std::string::npos);
  // KRL and RAPID hold 12 axes at most; the names are checked.
  options.name = "9lives";
  EXPECT_FALSE(
      ControllerProgramText(model, convention, poses, options, &text, &error));
  EXPECT_NE(error.find("must be a letter"), std::string::npos) << error;
}

// The shipped convention of data/kuka_iiwa14.urdf: at zero the controller's
// axes are A1 +z, A2 +y, A3 +z, A4 -y, A5 +z, A6 +y, A7 +z of the base (the
// LBR iiwa's published joint twists). The axis of each URDF joint at zero,
// from the flange's orientation under a small turn, times the file's sign,
// must be the controller's.
TEST(ControllerProgramTest, TheIiwaConventionMatchesTheControllersAxes) {
  const RobotModel model = Iiwa();
  ControllerConvention convention = IiwaConvention(model);
  std::string error;
  const Eigen::Vector3d kuka[] = {
      Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY(),
      Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitY(),
      Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY(),
      Eigen::Vector3d::UnitZ()};
  auto rotation = [&](const Eigen::VectorXd& q) {
    Measurement like;
    like.type = MeasurementType::kPose;
    like.joints = q;
    const Eigen::Vector3d r =
        PredictMeasurement(model, model.nominal, like).rotation;
    return Eigen::AngleAxisd(r.norm(), r.norm() > 0
                                           ? Eigen::Vector3d(r.normalized())
                                           : Eigen::Vector3d::UnitX())
        .toRotationMatrix();
  };
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(7);
  const Eigen::Matrix3d R0 = rotation(zero);
  for (int j = 0; j < 7; ++j) {
    const double h = 1e-6;
    Eigen::VectorXd q = zero;
    q[j] = h;  // a controller turn of +h / sign
    const Eigen::Matrix3d dR = rotation(q) * R0.transpose();
    const Eigen::Vector3d w(dR(2, 1) - dR(1, 2), dR(0, 2) - dR(2, 0),
                            dR(1, 0) - dR(0, 1));
    const Eigen::Vector3d axis = w / (2 * h) * convention.joints[j].sign;
    EXPECT_LT((axis - kuka[j]).norm(), 1e-6)
        << convention.joints[j].name << ": " << axis.transpose();
    EXPECT_EQ(convention.joints[j].offset, 0.0);
  }
}

// A pose at a joint limit is written at the limit or inside it, never a
// rounding step beyond it (the controller would stop at its software
// limit): the values read back and converted to activecal's joints are in
// the robot's range, in every language, with signs and an offset.
TEST(ControllerProgramTest, PosesAtTheLimitsAreWrittenInsideThem) {
  const RobotModel model = Iiwa();
  ControllerConvention convention = IiwaConvention(model);
  convention.joints[2].offset = 10 * M_PI / 180;
  PoseList poses;
  poses.joints.resize(2, 7);
  for (int j = 0; j < 7; ++j) {
    poses.joints(0, j) = model.links[j].joint_min;
    poses.joints(1, j) = model.links[j].joint_max;
  }
  for (ProgramLanguage language :
       {ProgramLanguage::kUrScript, ProgramLanguage::kKrl,
        ProgramLanguage::kRapid}) {
    SCOPED_TRACE(ProgramLanguageToString(language));
    ControllerProgramOptions options;
    options.language = language;
    std::string text;
    std::vector<std::vector<double>> rows;
    ASSERT_TRUE(ProgramMoves(model, convention, poses, options, &text, &rows));
    ASSERT_EQ(rows.size(), 2u) << text;
    for (int i = 0; i < 2; ++i) {
      const std::vector<double>& values = rows[i];
      ASSERT_EQ(values.size(), 7u);
      for (int j = 0; j < 7; ++j) {
        const ControllerJoint& c = convention.joints[j];
        const double q = (values[j] / UnitPerRad(language) - c.offset) / c.sign;
        // 1e-12 rad: the conversion back; a rounding step is 1e-9 at least.
        EXPECT_GE(q, model.links[j].joint_min - 1e-12)
            << "pose " << i << " joint " << j << ": " << values[j];
        EXPECT_LE(q, model.links[j].joint_max + 1e-12)
            << "pose " << i << " joint " << j << ": " << values[j];
        EXPECT_NEAR(q, poses.joints(i, j), 1e-6);
      }
    }
    if (language == ProgramLanguage::kKrl) {
      // A limit the URDF states in rad, a whole degree on the controller,
      // stays that degree (not a step inside it).
      EXPECT_NE(text.find("A4 -120.000000"), std::string::npos) << text;
      EXPECT_NE(text.find("E1 175.000000"), std::string::npos) << text;
    }
  }
}

// KRL: the speeds are whole percent (the system variables are INT), set
// the controller's way (BAS), for the external axes too, never below 1 %.
TEST(ControllerProgramTest, KrlSpeedsAreWholePercentForEveryAxis) {
  const RobotModel model = Iiwa();
  PoseList poses;
  poses.joints = Eigen::MatrixXd::Zero(1, 7);
  ControllerProgramOptions options;
  options.language = ProgramLanguage::kKrl;
  std::string text, error;
  ASSERT_TRUE(ControllerProgramText(model, IiwaConvention(model), poses,
                                    options, &text, &error))
      << error;
  EXPECT_NE(text.find("  BAS(#VEL_PTP, 10)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("  BAS(#ACC_PTP, 10)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("  $VEL_EXTAX[1] = 10\n"), std::string::npos) << text;
  EXPECT_NE(text.find("  $ACC_EXTAX[1] = 10\n"), std::string::npos) << text;
  // No loop variable (a name like AXIS would be KRL's type).
  EXPECT_EQ(text.find("DECL"), std::string::npos) << text;
  EXPECT_EQ(text.find("$VEL_EXTAX[2]"), std::string::npos) << text;
  options.speed_fraction = 0.004;
  EXPECT_FALSE(ControllerProgramText(model, IiwaConvention(model), poses,
                                     options, &text, &error));
  EXPECT_NE(error.find("the speed fraction must be in [0.01, 1]"),
            std::string::npos)
      << error;
}

TEST(ControllerProgramTest, BadConventionFilesAreNamed) {
  const RobotModel model = Iiwa();
  const std::string seven =
      "joints:\n"
      "  - {name: A1}\n  - {name: A2}\n  - {name: A3}\n  - {name: A4}\n"
      "  - {name: A5}\n  - {name: A6}\n";
  const struct {
    std::string text;
    std::string named;
  } cases[] = {
      {seven, "c.yaml:2:3: joints: has 6 entries, the robot 'kuka_iiwa14' 7"},
      {seven + "  - {name: A7, sign: 2}\n", "joints[6].sign: expected 1 or -1"},
      {seven + "  - {name: A7, offset_mm: 3}\n",
       "joints[6].offset_mm: joint 7 is revolute: use offset_deg or "
       "offset_rad"},
      {seven + "  - {name: A7, offset_deg: 1, offset_rad: 0}\n",
       "one offset per joint"},
      {seven + "  - {name: A7, joint: joint_a6}\n",
       "joints[6].joint: is for joint 'joint_a6', the robot's joint 7 is "
       "'joint_a7'"},
      {seven + "  - {name: A7, speed: 3}\n", "joints[6].speed: unknown field"},
      {"joint: []\n", "joint: unknown field"},
  };
  for (const auto& c : cases) {
    ControllerConvention convention;
    std::string error;
    EXPECT_FALSE(
        ParseControllerConvention(c.text, "c.yaml", model, &convention, &error))
        << c.text;
    EXPECT_NE(error.find(c.named), std::string::npos)
        << c.text << "\nerror: " << error;
  }
  ControllerConvention convention;
  std::string error;
  ASSERT_TRUE(ParseControllerConvention(
      seven + "  - {name: A7, sign: -1, offset_deg: 90}\n", "c.yaml", model,
      &convention, &error))
      << error;
  EXPECT_EQ(convention.joints[6].sign, -1);
  EXPECT_NEAR(convention.joints[6].offset, M_PI / 2, 1e-15);
  EXPECT_NEAR(ControllerJointValue(model, convention, ProgramLanguage::kKrl, 6,
                                   M_PI / 4),
              45.0, 1e-12);
  EXPECT_NEAR(ControllerJointValue(model, convention,
                                   ProgramLanguage::kUrScript, 6, M_PI / 4),
              M_PI / 4, 1e-15);
}

// The simulated cell through a pipe: the same pose gets the same answer
// whatever was asked between, a refused pose is answered with its status,
// and --die_after's exit comes at the request after that many measured.
std::vector<std::string> ServeSimulatedCell(
    const SimulatedCellOptions& options,
    const std::vector<std::string>& requests, int* status, bool* served) {
  int in[2], out[2];
  EXPECT_EQ(pipe(in), 0);
  EXPECT_EQ(pipe(out), 0);
  for (const std::string& r : requests) {
    const std::string line = r + "\n";
    EXPECT_EQ(write(in[1], line.data(), line.size()),
              static_cast<ssize_t>(line.size()));
  }
  close(in[1]);
  const RobotModel model = Puma560PaperModel();
  SimulatedCell cell(model, Puma560TrueParameters(), options);
  *status = 0;
  {
    LineChannel channel(in[0], out[1]);
    *served = cell.Serve(&channel, status);
  }
  std::vector<std::string> lines;
  LineChannel reader(out[0], out[0]);
  std::string line, error;
  while (reader.ReadLine(1.0, &line, &error) ==
         LineChannel::ReadResult::kLine) {
    lines.push_back(line);
  }
  return lines;
}

// The hello names the program and the robot as JSON strings, whatever
// characters the names hold (a quote or a backslash stays in the string).
TEST(SimulatedCellTest, HelloNamesTheProgramAsAJsonString) {
  const RobotModel model = Puma560PaperModel();
  DriverHello hello;
  for (const Link& link : model.links) hello.joint_names.push_back(link.name);
  hello.robot = model.name;
  SimulatedCellOptions options;
  options.program_name = R"(my "cell" \ 2)";
  options.seed = 7;
  int status = -1;
  bool served = false;
  const std::vector<std::string> lines = ServeSimulatedCell(
      options, {HelloMessage(hello), ByeMessage()}, &status, &served);
  ASSERT_EQ(lines.size(), 1u);
  std::string error;
  EXPECT_TRUE(ParseDriverHello(lines[0], &error)) << error;
  EXPECT_NE(lines[0].find(R"("driver":"my \"cell\" \\ 2")"), std::string::npos)
      << lines[0];
  EXPECT_NE(lines[0].find(R"("seed":7)"), std::string::npos) << lines[0];
  EXPECT_EQ(lines[0].find("\"about\""), std::string::npos) << lines[0];
}

TEST(SimulatedCellTest, AnswersArePerPoseAndTheCellDiesOnDemand) {
  const RobotModel model = Puma560PaperModel();
  DriverHello hello;
  for (const Link& link : model.links) hello.joint_names.push_back(link.name);
  hello.robot = model.name;
  const Eigen::VectorXd a = Eigen::VectorXd::Constant(6, 0.1);
  const Eigen::VectorXd b = Eigen::VectorXd::Constant(6, -0.3);
  SimulatedCellOptions options;
  options.seed = 5;
  std::string error;
  ASSERT_TRUE(options.IsValid(&error)) << error;
  int status = -1;
  bool served = false;
  const std::vector<std::string> lines = ServeSimulatedCell(
      options,
      {HelloMessage(hello), MeasureMessage(1, a), MeasureMessage(2, b),
       MeasureMessage(3, a), ByeMessage()},
      &status, &served);
  EXPECT_TRUE(served);
  EXPECT_EQ(status, 0);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_TRUE(ParseDriverHello(lines[0], &error)) << error;
  MeasurementReply first, again;
  ASSERT_TRUE(ParseMeasurementReply(lines[1], 1, 6, 1, &first, &error))
      << error;
  ASSERT_TRUE(ParseMeasurementReply(lines[3], 3, 6, 1, &again, &error))
      << error;
  EXPECT_EQ(first.status, MeasureStatus::kOk);
  EXPECT_EQ(*first.points_m[0], *again.points_m[0]);  // bit for bit
  EXPECT_EQ(first.joints, a);

  options.unreachable_fraction = 1.0;
  const std::vector<std::string> refused =
      ServeSimulatedCell(options, {MeasureMessage(1, a)}, &status, &served);
  ASSERT_EQ(refused.size(), 1u);
  MeasurementReply reply;
  ASSERT_TRUE(ParseMeasurementReply(refused[0], 1, 6, 1, &reply, &error));
  EXPECT_EQ(reply.status, MeasureStatus::kUnreachable);

  // Garbage at the second request: the reply to another id.
  options.unreachable_fraction = 0.0;
  ASSERT_TRUE(StringToDriverGarbage("wrong_id", &options.garbage));
  EXPECT_FALSE(StringToDriverGarbage("line", &options.garbage));
  options.garbage_at = 2;
  const std::vector<std::string> garbage = ServeSimulatedCell(
      options, {MeasureMessage(1, a), MeasureMessage(2, b)}, &status, &served);
  ASSERT_EQ(garbage.size(), 2u);
  EXPECT_TRUE(ParseMeasurementReply(garbage[0], 1, 6, 1, &reply, &error));
  EXPECT_FALSE(ParseMeasurementReply(garbage[1], 2, 6, 1, &reply, &error));
  options.garbage = DriverGarbage::kNone;

  // Its lines on stderr and its hello name the program the caller sets.
  options.die_after = 1;
  options.program_name = "my_cell";
  ::testing::internal::CaptureStderr();
  const std::vector<std::string> died = ServeSimulatedCell(
      options,
      {HelloMessage(hello), MeasureMessage(1, a), MeasureMessage(2, b)},
      &status, &served);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(),
            "my_cell: dying after 1 measurements (--die_after)\n");
  EXPECT_FALSE(served);
  EXPECT_EQ(status, 3);
  ASSERT_EQ(died.size(), 2u);
  EXPECT_NE(died[0].find("\"driver\":\"my_cell\""), std::string::npos)
      << died[0];
}

TEST(SimulatedCellTest, RunServesThePipeOrRefusesABadListenAddress) {
  const RobotModel model = Puma560PaperModel();
  SimulatedCellOptions options;
  options.listen = "host:";
  SimulatedCell refused(model, Puma560TrueParameters(), options);
  int status = -1, ready = 0;
  std::string error;
  EXPECT_FALSE(refused.Run(
      -1, -1, [&] { ++ready; }, &status, &error));
  EXPECT_EQ(error, "--listen must be PORT or HOST:PORT, got 'host:'");
  EXPECT_EQ(ready, 0);  // nothing is written for a run that fails

  // Without listen: `ready`, then one conversation on the fds.
  int in[2], out[2];
  ASSERT_EQ(pipe(in), 0);
  ASSERT_EQ(pipe(out), 0);
  const std::string bye = ByeMessage() + "\n";
  ASSERT_EQ(write(in[1], bye.data(), bye.size()),
            static_cast<ssize_t>(bye.size()));
  close(in[1]);
  options.listen.clear();
  SimulatedCell cell(model, Puma560TrueParameters(), options);
  EXPECT_TRUE(cell.Run(
      in[0], out[1], [&] { ++ready; }, &status, &error))
      << error;
  EXPECT_EQ(ready, 1);
  EXPECT_EQ(status, 0);
  close(in[0]);
  close(out[0]);
  close(out[1]);
}

TEST(SimulatedCellTest, OptionsAndListenAddressesAreChecked) {
  SimulatedCellOptions options;
  std::string error;
  options.perturb_rad = -1;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_EQ(error, "perturb_rad must be >= 0");
  options.perturb_rad = 0;
  options.not_visible_fraction = 1.5;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_EQ(error, "not_visible_fraction must be in [0, 1]");

  std::string host;
  int port = -1;
  ASSERT_TRUE(ParseListenAddress("8123", &host, &port, &error));
  EXPECT_EQ(host, "127.0.0.1");
  EXPECT_EQ(port, 8123);
  ASSERT_TRUE(ParseListenAddress("0.0.0.0:0", &host, &port, &error));
  EXPECT_EQ(host, "0.0.0.0");
  EXPECT_EQ(port, 0);
  EXPECT_FALSE(ParseListenAddress("host:", &host, &port, &error));
  EXPECT_EQ(error, "must be PORT or HOST:PORT, got 'host:'");
  // 16 bits: the last port, then one past it, one that wraps to 4464
  // modulo 65536, and one beyond an int are refused by name.
  ASSERT_TRUE(ParseListenAddress("65535", &host, &port, &error));
  EXPECT_EQ(port, 65535);
  for (const char* bad : {"65536", "70000", "localhost:99999999999"}) {
    EXPECT_FALSE(ParseListenAddress(bad, &host, &port, &error)) << bad;
    EXPECT_EQ(error.rfind("the port must be in 0..65535, got '", 0), 0u)
        << error;
  }

  // No true values and no perturbation: nothing to simulate from.
  const RobotModel model = Puma560PaperModel();
  Eigen::VectorXd truth;
  EXPECT_FALSE(MakeSimulatedCellTruth(model, Eigen::VectorXd(), options, &truth,
                                      &error));
  options.perturb_m = 1e-3;
  ASSERT_TRUE(
      MakeSimulatedCellTruth(model, Eigen::VectorXd(), options, &truth, &error))
      << error;
  EXPECT_GT((truth - model.nominal).norm(), 0.0);
}

}  // namespace
}  // namespace activecal
