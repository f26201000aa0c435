// Marginalisation of old states into a linear(ised) Gaussian prior by the Schur complement.
//
// Residual blocks touching the states to remove are linearised at the current estimate; the
// Hessian of those residuals is split into removed (m) and kept (r) parameters and the kept part
// becomes the prior  || J_p (x - x0) + r_p ||^2  with J_p^T J_p = H_rr - H_rm H_mm^-1 H_mr.
//
// Blocks declared constant (e.g. inverse depths fixed by depth verification) are not variables:
// they take part in residual evaluation but contribute no rows/columns and are never marginalised.
// Pose blocks (7 ambient doubles) use the 6-dim tangent of PoseManifold.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <Eigen/Core>
#include <memory>
#include <set>
#include <unordered_map>
#include <vector>

namespace rgbdi::estimator {

struct MarginalizationResidual {
  std::shared_ptr<ceres::CostFunction> cost;
  std::shared_ptr<ceres::LossFunction> loss;  ///< may be null
  std::vector<double*> blocks;                ///< parameter block addresses, in cost order
};

class MarginalizationInfo {
 public:
  void add(MarginalizationResidual r) { residuals_.push_back(std::move(r)); }
  /// Linearises all residuals and computes the prior on the blocks not in `remove`.
  /// `constant` lists blocks that are held constant (not variables).
  /// Returns false when nothing remains to keep.
  bool marginalize(const std::set<const double*>& remove, const std::set<const double*>& constant);

  /// Kept blocks (addresses at marginalisation time), their ambient sizes and linearisation points.
  const std::vector<double*>& keptBlocks() const { return kept_blocks_; }
  const std::vector<int>& keptSizes() const { return kept_sizes_; }
  const std::vector<Eigen::VectorXd>& keptValues() const { return kept_values_; }
  const Eigen::MatrixXd& jacobian() const { return lin_jacobian_; }
  const Eigen::VectorXd& residual() const { return lin_residual_; }
  /// jacobian()^T jacobian(): the prior's Gauss-Newton Hessian, constant as the prior is linear.
  const Eigen::MatrixXd& hessian() const { return lin_hessian_; }
  /// x - x0 over the kept blocks in their tangent spaces (poses: PoseManifold::Minus), for the
  /// values at `parameters` (one pointer per kept block, in keptBlocks() order).
  void tangentDelta(double const* const* parameters, Eigen::VectorXd& dx) const;
  /// The prior's cost 1/2 |r|^2, r = residual() + jacobian() (x - x0), at those values; with
  /// `gradient` also J^T r (its Hessian is hessian()).
  double evaluate(double const* const* parameters, Eigen::VectorXd* gradient = nullptr) const;
  /// Adds the prior's Gauss-Newton terms at those values to normal equations: g += J^T r and
  /// H += hessian(), kept block k at tangent offset offsets[k] of H and g (-1: a block not in
  /// them, left out); with `lower_only` only the blocks whose row offset is at least their
  /// column offset. Returns the prior's cost.
  double addNormalEquations(double const* const* parameters, const std::vector<int>& offsets,
                            bool lower_only, Eigen::MatrixXd& H, Eigen::VectorXd& g) const;
  /// Rewrites the kept block addresses after the window shifted (old address -> new address).
  void remapBlocks(const std::unordered_map<const double*, double*>& remap);

  static int tangentSize(int ambient) { return ambient == 7 ? 6 : ambient; }

 private:
  std::vector<MarginalizationResidual> residuals_;
  std::vector<double*> kept_blocks_;
  std::vector<int> kept_sizes_;
  std::vector<Eigen::VectorXd> kept_values_;
  Eigen::MatrixXd lin_jacobian_;
  Eigen::VectorXd lin_residual_;
  Eigen::MatrixXd lin_hessian_;
};

/// The prior as a Ceres cost function on the kept blocks.
class MarginalizationFactor final : public ceres::CostFunction {
 public:
  explicit MarginalizationFactor(std::shared_ptr<const MarginalizationInfo> info);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;
  const MarginalizationInfo& info() const { return *info_; }

 private:
  std::shared_ptr<const MarginalizationInfo> info_;
};

}  // namespace rgbdi::estimator
