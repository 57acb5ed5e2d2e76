#include "activecal/estimation/registration_fit.h"

#include <glog/logging.h>

#include "activecal/core/parameter_sets.h"
#include "activecal/estimation/registration.h"
#include "activecal/estimation/parameter_reduction.h"

namespace activecal {

void FitRegistration(const RobotModel& model, const Eigen::VectorXd& geometry,
                     const std::vector<Measurement>& measurements,
                     const IdentificationOptions& options,
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
  // Distances carry no position: they leave the base where it is.
  if (m.base.convention == LinkConvention::kFrame && num_points > 0) {
    RegistrationSummary closed_form;
    if (!RegisterBaseFrame(m, measurements, &start, &closed_form)) {
      summary->message = closed_form.message;
      return;
    }
  }
  std::vector<DroppedParameter> dropped;
  if (!ApplyAndReduceParameterSet(ParameterSet::kRegistration, measurements,
                                  options.rotation_weight_m_per_rad, &m, &start,
                                  &dropped, &error)) {
    summary->message = "registration fit: " + error;
    return;
  }
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

}  // namespace activecal
