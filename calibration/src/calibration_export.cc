#include "activecal/calibration/calibration_export.h"

#include <glog/logging.h>

#include "activecal/io/csv_files.h"
#include "activecal/io/urdf_export.h"

namespace activecal {

bool MakeCalibratedUrdf(const RobotModel& model,
                        const Eigen::VectorXd& parameters,
                        const std::vector<Measurement>& check,
                        const CalibratedUrdfOptions& options,
                        CalibratedUrdf* urdf, std::string* error) {
  CHECK(urdf != nullptr);
  CHECK(error != nullptr);
  *urdf = CalibratedUrdf();
  UrdfChainOptions chain = options.chain;
  if (!options.source_path.empty()) {
    std::string xml;
    if (!ReadTextFile(options.source_path, &xml, error) ||
        !CalibratedUrdfText(xml, options.source_path, chain, model, parameters,
                            &urdf->text, &urdf->warnings, error)) {
      return false;
    }
  } else {
    urdf->text = UrdfFromModel(model, parameters, &urdf->warnings);
    chain.base_link = "base_link";
    chain.tip_link = "tip";
  }
  // Reload what is written: it must predict every measured point.
  if (!CheckUrdfAgainstModel(urdf->text, options.output_path, chain, model,
                             parameters, check, &urdf->worst_m, error)) {
    *error = "the written URDF does not reload: " + *error;
    return false;
  }
  if (!(urdf->worst_m <= options.tolerance_m)) {
    *error = "the written URDF predicts the measurements up to " +
             std::to_string(urdf->worst_m) +
             " m away from the calibrated model (more than 1e-9 m)" +
             (urdf->warnings.empty() ? "" : ": " + urdf->warnings[0]);
    return false;
  }
  return true;
}

}  // namespace activecal
