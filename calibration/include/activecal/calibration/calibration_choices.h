// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The named choices of a calibration, and the values checked with them, as
// text and plain values (what activecal_identify's flags and the Python
// module's keywords give), set into CalibrationOptions in one call with
// the choices each message names.
//
//   CalibrationChoices choices;
//   choices.model_selection = "cv";
//   choices.robust_loss = "huber";
//   if (!SetCalibrationChoices(model, choices, OptionSpelling::kFlags,
//                              &options, &error)) ...

#ifndef ACTIVECAL_CALIBRATION_CALIBRATION_CHOICES_H_
#define ACTIVECAL_CALIBRATION_CALIBRATION_CHOICES_H_

#include <string>

#include "activecal/calibration/calibrate.h"
#include "activecal/calibration/calibration_report.h"
#include "activecal/calibration/calibration_setup.h"
#include "activecal/calibration/defaults.h"
#include "activecal/core/robot_model.h"

namespace activecal {

struct CalibrationChoices {
  // auto, none, validation or cv (StringToModelSelectionMethod).
  std::string model_selection = defaults::kModelSelection;
  // 1se_most, min, 1se or ftest (StringToSelectionRule).
  std::string selection_rule = defaults::kSelectionRule;
  // significance or jacobian (StringToParameterRanking).
  std::string selection_ranking = defaults::kSelectionRanking;
  // The joint error families offered (MakeTermFamilies).
  TermFamilyOptions terms;
  // none, huber or cauchy (StringToRobustLoss).
  std::string robust_loss = defaults::kRobustLoss;
  // Its scale (m) and the outliers' probability
  // (IdentificationOptions::outlier_probability), set as they are
  // (CalibrationOptions::IsValid checks them).
  double robust_scale_m = 0.0;
  double outlier_probability = IdentificationOptions().outlier_probability;
  // Of 6D pose orientation rows, m per rad: finite and > 0 (the option
  // rotation_weight).
  double rotation_weight = defaults::kRotationWeightMPerRad;
  // off, on or auto (StringToLearnedResidualMode).
  std::string learned_residual = "off";
};

// Sets options->model_selection, selection_rule, selection_ranking,
// term_families, identification.robust_loss, robust_scale_m,
// outlier_probability and rotation_weight_m_per_rad, and
// learned_residual.mode from
// `choices`, checked in that order; the other fields are left as they
// are. False at the first bad value with one line naming the option in
// `spelling` ("--model_selection must be auto, none, validation or cv, got
// 'x'", MakeTermFamilies' messages, "--rotation_weight must be finite and
// > 0 (m per rad), got 0.000000"); the fields before it are set.
bool SetCalibrationChoices(const RobotModel& model,
                           const CalibrationChoices& choices,
                           OptionSpelling spelling, CalibrationOptions* options,
                           std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_CALIBRATION_CHOICES_H_
