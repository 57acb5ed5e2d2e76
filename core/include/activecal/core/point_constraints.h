// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Fixed points for a calibration without a tracker: the marker placed at a
// point (a ball in a socket, a stylus in a cone) from several
// configurations, the point's coordinates unknown (measurement.h, kPoint
// rows), optionally with known distances between the points
// (kPointDistance rows).
//
// Each label is 3 unknowns of the fit. Eliminated (projected out of the
// Jacobian), they leave what the rows say about the robot: the spread of
// the predicted points of one label about their mean. So a label needs at
// least two rows, and a known distance needs both its labels among the
// point rows.

#ifndef ACTIVECAL_CORE_POINT_CONSTRAINTS_H_
#define ACTIVECAL_CORE_POINT_CONSTRAINTS_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// The labels of the fixed points of `measurements` (point rows, then point
// distances), each once, in order of first appearance.
std::vector<std::string> PointLabels(
    const std::vector<Measurement>& measurements);

// The position of `label` in `labels` (a point's in PointLabels order, a
// plane's in PlaneLabels order); labels.size() when it is not there.
int LabelIndex(const std::vector<std::string>& labels,
               const std::string& label);

// True when some measurement involves a fixed point.
bool HasPointRows(const std::vector<Measurement>& measurements);

// Every label of a point row has at least two rows, every label of a point
// distance has point rows. False with a message naming the label and the
// (0-based) measurement otherwise.
bool CheckPointLabels(const std::vector<Measurement>& measurements,
                      std::string* error);

// The mean predicted point of each label's point rows at `parameters`
// (full vector), labels in PointLabels order; a label without point rows
// gets zero. Used to start the fit.
std::vector<Eigen::Vector3d> MeanPointPositions(
    const RobotModel& model, const Eigen::VectorXd& parameters,
    const std::vector<Measurement>& measurements,
    const std::vector<std::string>& labels);

// Moves the joints *q (a start) to the nearest configuration found by
// Gauss-Newton, minimum-norm steps, at which the model at `parameters`
// puts marker `marker` at `target`, to within tolerance_m. Joint ranges
// are not enforced (the moves this is meant for are of micro- to
// milliradians). False, *q the best found, when it does not get there in
// max_iterations steps.
bool ReachPoint(const RobotModel& model, const Eigen::VectorXd& parameters,
                int marker, const Eigen::Vector3d& target, Eigen::VectorXd* q,
                double tolerance_m = 1e-12, int max_iterations = 50);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_POINT_CONSTRAINTS_H_
