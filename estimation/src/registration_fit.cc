// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/registration_fit.h"

#include <glog/logging.h>

#include "activecal/core/parameter_sets.h"
#include "activecal/estimation/parameter_reduction.h"
#include "activecal/estimation/registration.h"

namespace activecal {
namespace {

// within_free: fit only the registration parameters free in `model`.
void Fit(const RobotModel& model, const Eigen::VectorXd& geometry,
         const std::vector<Measurement>& measurements,
         const IdentificationOptions& options, bool within_free,
         RegistrationFitSummary* summary) {
  CHECK(summary != nullptr);
  *summary = RegistrationFitSummary();
  RobotModel m = model;
  Eigen::VectorXd start = geometry;
  std::string error;
  if (!m.CheckParameters(start, &error)) {
    summary->message = "registration fit: " + error;
    return;
  }
  int num_points = 0;
  for (const Measurement& x : measurements) {
    num_points += x.type != MeasurementType::kDistance;
  }
  bool base_free = true;
  for (int j = 0; j < m.block_size(0); ++j) base_free &= model.IsFree(j);
  // Distances carry no position: they leave the base where it is.
  if (m.base.convention == LinkConvention::kFrame && num_points > 0 &&
      (base_free || !within_free)) {
    RegistrationSummary closed_form;
    if (!RegisterBaseFrame(m, measurements, &start, &closed_form)) {
      summary->message = closed_form.message;
      return;
    }
  }
  std::vector<HeldParameter> dropped;
  FreeSet free;
  if (!ReduceParameterSet(m, ParameterSet::kRegistration, measurements,
                          options.rotation_weight_m_per_rad, &start, &free,
                          &dropped, &error)) {
    summary->message = "registration fit: " + error;
    return;
  }
  if (within_free) {
    // What the reduction kept, less what `model` holds: those keep their
    // given values (the reduction moved free marker points to a generic
    // point).
    for (int i = 0; i < m.num_parameters(); ++i) {
      if (free.Contains(i) && !model.IsFree(i)) {
        free.Set(i, false);
        start[i] = geometry[i];
      }
    }
    if (free.empty()) {
      summary->message =
          "registration fit: no base or marker parameter is free in the "
          "calibrated model";
      return;
    }
  }
  m = WithFreeSet(m, free);
  summary->names = m.FreeParameterNames();
  Identify(m, measurements, start, options, &summary->identification);
  const IdentificationSummary& id = summary->identification;
  summary->termination_type = id.termination_type;
  summary->message = "registration fit: " + id.message;
  if (id.parameters.size() == geometry.size()) {
    summary->parameters = id.parameters;
    summary->rms_m = id.rms_m;
  }
}

}  // namespace

void FitRegistration(const RobotModel& model, const Eigen::VectorXd& geometry,
                     const std::vector<Measurement>& measurements,
                     const IdentificationOptions& options,
                     RegistrationFitSummary* summary) {
  Fit(model, geometry, measurements, options, false, summary);
}

void FitRegistrationOfFreeSet(const RobotModel& model,
                              const Eigen::VectorXd& geometry,
                              const std::vector<Measurement>& measurements,
                              const IdentificationOptions& options,
                              RegistrationFitSummary* summary) {
  Fit(model, geometry, measurements, options, true, summary);
}

}  // namespace activecal
