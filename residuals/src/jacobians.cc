#include "activecal/residuals/jacobians.h"

#include <atomic>
#include <memory>
#include <vector>

#include "activecal/core/parallel.h"
#include "activecal/residuals/position_residual.h"

namespace activecal {
namespace {

// Evaluates PositionResidual Jacobians for one model and parameter vector,
// asking Ceres only for blocks that hold free parameters. Not thread-safe:
// use one per thread.
class JacobianEvaluator {
 public:
  JacobianEvaluator(std::shared_ptr<const RobotModel> model,
                    const Eigen::VectorXd& parameters)
      : model_(std::move(model)), parameters_(parameters) {
    const RobotModel& m = *model_;
    blocks_ = BlockPointers(m, parameters_.data());
    block_jacobians_.resize(m.num_blocks());
    jacobian_ptrs_.assign(m.num_blocks(), nullptr);
    for (int b = 0; b < m.num_blocks(); ++b) {
      const size_t before = columns_.size();
      for (int j = 0; j < m.block_size(b); ++j) {
        if (m.IsFree(m.block_offset(b) + j)) columns_.push_back({b, j});
      }
      // Ask Ceres only for the blocks that hold a free parameter.
      if (columns_.size() > before) {
        block_jacobians_[b].resize(3 * m.block_size(b));
        jacobian_ptrs_[b] = block_jacobians_[b].data();
      }
    }
  }

  // Writes the 3 x num_free Jacobian, row-major, to out.
  bool Evaluate(const Eigen::VectorXd& q, double* out) {
    std::unique_ptr<ceres::CostFunction> cost(
        PositionResidual::Create(model_, q, Eigen::Vector3d::Zero()));
    double residuals[3];
    if (!cost->Evaluate(blocks_.data(), residuals, jacobian_ptrs_.data())) {
      return false;
    }
    const int p = static_cast<int>(columns_.size());
    for (int c = 0; c < p; ++c) {
      const auto [b, j] = columns_[c];
      const int size = model_->block_size(b);
      for (int r = 0; r < 3; ++r) {
        out[r * p + c] = block_jacobians_[b][r * size + j];
      }
    }
    return true;
  }

 private:
  std::shared_ptr<const RobotModel> model_;
  Eigen::VectorXd parameters_;
  std::vector<const double*> blocks_;
  std::vector<std::vector<double>> block_jacobians_;
  std::vector<double*> jacobian_ptrs_;
  std::vector<std::pair<int, int>> columns_;  // (block, index in block)
};

bool CheckInputs(const RobotModel& model, const Eigen::VectorXd& parameters,
                 std::string* error) {
  if (!model.Validate(error)) return false;
  if (!model.CheckParameters(parameters, error)) return false;
  if (model.num_free() == 0) {
    if (error) *error = "robot '" + model.name + "': no free parameters";
    return false;
  }
  return true;
}

}  // namespace

bool PositionJacobian(const RobotModel& model,
                      const Eigen::VectorXd& parameters,
                      const Eigen::VectorXd& joints, Eigen::MatrixXd* jacobian,
                      std::string* error) {
  if (!CheckInputs(model, parameters, error)) return false;
  if (!model.CheckJointValues(joints, error)) return false;
  JacobianEvaluator evaluator(std::make_shared<const RobotModel>(model),
                              parameters);
  RowMatrixXd J(3, model.num_free());
  if (!evaluator.Evaluate(joints, J.data())) {
    if (error) *error = "Jacobian evaluation failed";
    return false;
  }
  *jacobian = J;
  return true;
}

bool PoolPositionJacobians(const RobotModel& model,
                           const Eigen::VectorXd& parameters,
                           const Eigen::MatrixXd& joints,
                           const PoolJacobianOptions& options,
                           RowMatrixXd* stacked, std::string* error) {
  if (!CheckInputs(model, parameters, error)) return false;
  if (joints.cols() != model.num_joints()) {
    if (error) {
      *error = "pool: expected " + std::to_string(model.num_joints()) +
               " joint values per pose, got " + std::to_string(joints.cols());
    }
    return false;
  }
  const int64_t n = joints.rows();
  for (int64_t i = 0; i < n; ++i) {
    std::string why;
    if (!model.CheckJointValues(joints.row(i).transpose(), &why)) {
      if (error) *error = "pool pose " + std::to_string(i) + ": " + why;
      return false;
    }
  }
  const int p = model.num_free();
  stacked->resize(3 * n, p);
  auto shared = std::make_shared<const RobotModel>(model);
  std::atomic<int64_t> failed{-1};
  ParallelFor(n, options.num_threads, [&](int64_t begin, int64_t end, int) {
    JacobianEvaluator evaluator(shared, parameters);
    for (int64_t i = begin; i < end; ++i) {
      if (!evaluator.Evaluate(joints.row(i).transpose(),
                              stacked->data() + 3 * i * p)) {
        failed = i;
        return;
      }
    }
  });
  if (failed >= 0) {
    if (error) {
      *error = "Jacobian evaluation failed at pool pose " +
               std::to_string(failed.load());
    }
    return false;
  }
  return true;
}

}  // namespace activecal
