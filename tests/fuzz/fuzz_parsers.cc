// libFuzzer targets of the file parsers: whatever the bytes, a parser
// returns true or false with a message; it never crashes, reads out of
// bounds, overflows or hangs. One binary per parser, chosen at compile time
// by ACTIVECAL_FUZZ_TARGET (1 robot YAML, 2 poses CSV, 3 measurements CSV).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/csv_files.h"
#include "activecal/core/puma560.h"
#include "activecal/core/robot_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string error;
#if ACTIVECAL_FUZZ_TARGET == 1
  activecal::RobotDescription robot;
  if (activecal::ParseRobotDescription(text, "fuzz.yaml", &robot, &error)) {
    // A description that loads must be valid and write back loadably.
    std::string why;
    if (!robot.model.Validate(&why)) __builtin_trap();
    activecal::RobotDescription back;
    if (!activecal::ParseRobotDescription(
            activecal::RobotFileText(robot.model, robot.model.nominal), "back",
            &back, &why)) {
      __builtin_trap();
    }
  } else if (error.empty()) {
    __builtin_trap();  // a failure always says why
  }
#else
  static const activecal::RobotModel model = activecal::Puma560PaperModel();
#if ACTIVECAL_FUZZ_TARGET == 2
  activecal::PoseList poses;
  const bool ok =
      activecal::ParsePosesCsv(text, "fuzz.csv", model, true, &poses, &error);
  if (ok) {
    for (int i = 0; i < poses.joints.rows(); ++i) {
      if (!model.CheckJointValues(poses.joints.row(i).transpose(), &error)) {
        __builtin_trap();
      }
    }
  }
#else
  std::vector<activecal::Measurement> measurements;
  const bool ok = activecal::ParseMeasurementsCsv(text, "fuzz.csv", model,
                                                  &measurements, &error);
  if (ok) {
    for (const activecal::Measurement& m : measurements) {
      if (!activecal::CheckMeasurement(model, m, &error)) __builtin_trap();
    }
  }
#endif
  if (!ok && error.empty()) __builtin_trap();
#endif
  return 0;
}
