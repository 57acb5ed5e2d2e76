// The CSV files of the calibration workflow (docs/formats.md):
//
//   poses        what to run on the robot: pose_index, then each joint in SI
//                units (q1_rad, or q3_m for a prismatic joint) and in the
//                unit a robot pendant shows (q1_deg, q3_mm). Reading needs
//                one of the two per joint; when both are there they must
//                agree.
//   measurements what the device reported: type (position, pose, distance),
//                the joints, and the measured values: x_m, y_m, z_m;
//                rx_rad, ry_rad, rz_rad (pose: rotation vector); the second
//                pose's joints q1_rad_2 ... and distance_m (distance).
//                Fields a row's type does not use are left empty. An
//                optional "marker" column names the model's marker a row
//                measured (its name, or its number 1, 2, ...; empty or no
//                column: the first); written when a measurement is not of
//                the first marker.
//
// Lines starting with '#' are comments. Every reader names the file, the
// line and the column of a problem: "poses.csv:7: q3_rad: expected a
// number, got 'abc'".

#ifndef ACTIVECAL_CORE_CSV_FILES_H_
#define ACTIVECAL_CORE_CSV_FILES_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// The SI column name of joint j (0-based): "q1_rad" or "q1_m".
std::string JointColumn(const RobotModel& model, int j);

struct PoseList {
  Eigen::MatrixXd joints;             // one pose per row, SI units
  std::vector<int64_t> pose_indices;  // from pose_index, or 0, 1, 2, ...
};

std::string PosesCsvText(const RobotModel& model, const PoseList& poses);
// Checks each pose against the joint limits; with reject_duplicates, two
// identical poses are an error naming both lines.
bool ParsePosesCsv(const std::string& text, const std::string& source,
                   const RobotModel& model, bool reject_duplicates,
                   PoseList* poses, std::string* error);
bool ReadPosesCsv(const std::string& path, const RobotModel& model,
                  bool reject_duplicates, PoseList* poses, std::string* error);

std::string MeasurementsCsvText(const RobotModel& model,
                                const std::vector<Measurement>& measurements);
bool ParseMeasurementsCsv(const std::string& text, const std::string& source,
                          const RobotModel& model,
                          std::vector<Measurement>* measurements,
                          std::string* error);
bool ReadMeasurementsCsv(const std::string& path, const RobotModel& model,
                         std::vector<Measurement>* measurements,
                         std::string* error);

// Reads a whole file; false with "<path>: cannot open ..." on failure.
bool ReadTextFile(const std::string& path, std::string* text,
                  std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_CSV_FILES_H_
