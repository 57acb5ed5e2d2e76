// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/calibration_choices.h"

#include <cmath>

namespace activecal {
namespace {

// The enum value of `text` (a StringToX), or false with "<p><name> must be
// <choices>, got '<text>'".
template <typename Enum>
bool Choice(bool (*string_to)(const std::string&, Enum*), const char* name,
            const std::string& text, const char* choices, const std::string& p,
            Enum* value, std::string* error) {
  if (string_to(text, value)) return true;
  *error = p + name + " must be " + choices + ", got '" + text + "'";
  return false;
}

}  // namespace

bool SetCalibrationChoices(const RobotModel& model,
                           const CalibrationChoices& choices,
                           OptionSpelling spelling, CalibrationOptions* options,
                           std::string* error) {
  const std::string p = spelling == OptionSpelling::kFlags ? "--" : "";
  IdentificationOptions& fit = options->identification;
  if (!Choice(StringToModelSelectionMethod, "model_selection",
              choices.model_selection, "auto, none, validation or cv", p,
              &options->model_selection, error) ||
      !Choice(StringToSelectionRule, "selection_rule", choices.selection_rule,
              "1se_most, min, 1se or ftest", p, &options->selection_rule,
              error) ||
      !Choice(StringToParameterRanking, "selection_ranking",
              choices.selection_ranking, "significance or jacobian", p,
              &options->selection_ranking, error) ||
      !MakeTermFamilies(model, choices.terms, spelling, &options->term_families,
                        error) ||
      !Choice(StringToRobustLoss, "robust_loss", choices.robust_loss,
              "none, huber or cauchy", p, &fit.robust_loss, error)) {
    return false;
  }
  fit.robust_scale_m = choices.robust_scale_m;
  fit.outlier_probability = choices.outlier_probability;
  const double weight = choices.rotation_weight;
  if (!(weight > 0) || !std::isfinite(weight)) {
    *error = p + "rotation_weight must be finite and > 0 (m per rad), got " +
             std::to_string(weight);
    return false;
  }
  fit.rotation_weight_m_per_rad = weight;
  return Choice(StringToLearnedResidualMode, "learned_residual",
                choices.learned_residual, "off, on or auto", p,
                &options->learned_residual.mode, error);
}

}  // namespace activecal
