// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/targets_csv.h"

#include <cmath>
#include <sstream>

#include "activecal/io/csv_files.h"
#include "csv_columns.h"
#include "line_error.h"
#include "number_text.h"

namespace activecal {

using internal::ShortestText;

bool ParseTargetsCsv(const std::string& text, const std::string& source,
                     const RobotModel& model, const TargetsCsvOptions& options,
                     TargetList* targets, std::vector<std::string>* notes,
                     std::string* error) {
  // The columns of the measurements CSV (csv_columns.h).
  internal::PointTable table;
  if (!internal::ParsePointTable(text, source, model, options.columns_strict,
                                 &table, error)) {
    return false;
  }
  auto fail = [&](int row, const std::string& what) {
    if (error) {
      *error = internal::LineError(source, table.lines[row], "row", what);
    }
    return false;
  };
  const int n = static_cast<int>(table.lines.size());
  for (int i = 0; i < n; ++i) {
    if (table.rotation_given_as_vector) {
      const double angle = table.rotation_vectors.row(i).norm();
      if (angle > M_PI + 1e-12) {
        return fail(i, "the rotation vector has angle " + ShortestText(angle) +
                           " rad > pi: write the same rotation with an angle "
                           "in [0, pi]");
      }
    }
    if (table.joints.rows() > 0) {
      std::string why;
      if (!model.CheckJointValues(table.joints.row(i).transpose(), &why)) {
        return fail(i, "start joints: " + why);
      }
    }
  }
  TargetList out;
  out.pose_indices = std::move(table.pose_indices);
  out.points = std::move(table.points);
  out.rotation_vectors = std::move(table.rotation_vectors);
  out.start_joints = std::move(table.joints);
  *targets = std::move(out);
  if (notes) {
    notes->clear();
    if (!table.unread.empty()) {
      notes->push_back(internal::UnreadColumnsNote(source, table.unread));
    }
  }
  return true;
}

bool ParseTargetsCsv(const std::string& text, const std::string& source,
                     const RobotModel& model, TargetList* targets,
                     std::string* error) {
  return ParseTargetsCsv(text, source, model, TargetsCsvOptions(), targets,
                         nullptr, error);
}

bool ReadTargetsCsv(const std::string& path, const RobotModel& model,
                    const TargetsCsvOptions& options, TargetList* targets,
                    std::vector<std::string>* notes, std::string* error) {
  std::string text;
  if (!ReadTextFile(path, &text, error)) return false;
  return ParseTargetsCsv(text, path, model, options, targets, notes, error);
}

bool ReadTargetsCsv(const std::string& path, const RobotModel& model,
                    TargetList* targets, std::string* error) {
  return ReadTargetsCsv(path, model, TargetsCsvOptions(), targets, nullptr,
                        error);
}

std::string TargetsCsvText(const RobotModel& model, const TargetList& targets) {
  const int n = static_cast<int>(targets.points.rows());
  const bool rotation = targets.rotation_vectors.rows() == n && n > 0;
  const bool joints = targets.start_joints.rows() == n && n > 0;
  std::ostringstream out;
  out << "pose_index,x_m,y_m,z_m";
  if (rotation) out << ",rx_rad,ry_rad,rz_rad";
  if (joints) {
    for (int j = 0; j < model.num_joints(); ++j) {
      out << "," << JointColumn(model, j);
    }
  }
  out << "\n";
  for (int i = 0; i < n; ++i) {
    out << (i < static_cast<int>(targets.pose_indices.size())
                ? targets.pose_indices[i]
                : i);
    for (int a = 0; a < 3; ++a)
      out << "," << ShortestText(targets.points(i, a));
    if (rotation) {
      for (int a = 0; a < 3; ++a) {
        out << "," << ShortestText(targets.rotation_vectors(i, a));
      }
    }
    if (joints) {
      for (int j = 0; j < model.num_joints(); ++j) {
        out << "," << ShortestText(targets.start_joints(i, j));
      }
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace activecal
