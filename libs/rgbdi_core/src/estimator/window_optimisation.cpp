#include "estimator/window_optimisation.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <memory>
#include <type_traits>

#include "estimator/window_state.h"
#include "rgbdi/estimator/gauge_prior.h"
#include "rgbdi/estimator/ground_plane_factor.h"
#include "rgbdi/estimator/scalar_prior.h"
#include "rgbdi/estimator/speed_bias_prior.h"
#include "rgbdi/imu/imu_factor.h"
#include "rgbdi/imu/preintegration.h"

namespace rgbdi::estimator {

namespace {

// Sqrt information of the gauge prior [1/m, 1/rad]: stiff enough to act as a constraint, soft
// enough to keep the normal equations well conditioned.
constexpr double kGaugeStiffness = 1e4;
// [1/m] lower bound of a solved inverse depth (1 km): a feature beyond it carries no depth
// information, and the bound keeps a step from flipping it behind the camera.
constexpr double kMinInverseDepth = 1e-3;

}  // namespace

WindowOptimisation::WindowOptimisation(const EstimatorOptions& opt, const WindowCostModel& model)
    : opt_(opt), model_(model) {}

WindowUpdate WindowOptimisation::run(WindowState& state, bool single_step) {
  FrameWindow& window = state.frames;
  double* td = state.time_offset;
  WindowSolver& solver = solver_;
  solver.clear();
  // The factors other than the reprojections live for this update only.
  std::vector<std::unique_ptr<ceres::CostFunction>> factors;
  auto addResidual = [&](const ceres::CostFunction* f, const ceres::LossFunction* loss,
                         std::initializer_list<double*> blocks) {
    residual_blocks_.assign(blocks);
    solver.addResidual(f, loss, residual_blocks_);
  };
  auto add = [&](ceres::CostFunction* f, const ceres::LossFunction* loss,
                 std::initializer_list<double*> blocks) {
    factors.emplace_back(f);
    addResidual(f, loss, blocks);
  };
  // Factors are reused from one update to the next (a thousand fresh ones per update cost
  // allocations): the pool's next unused one is reset, or a new one appended.
  auto reused = [&](auto& pool, std::size_t& used, const FeatureMeasurement& i,
                    const FeatureMeasurement& j) {
    using Factor = typename std::decay_t<decltype(pool)>::value_type::element_type;
    if (used == pool.size())
      pool.push_back(
          std::make_unique<Factor>(i, j, model_.T_body_cam, model_.reprojection_sqrt_info));
    else
      pool[used]->reset(i, j, model_.T_body_cam, model_.reprojection_sqrt_info);
    return pool[used++].get();
  };
  std::size_t reprojections = 0, rs_reprojections = 0;
  auto reprojection = [&](const FeatureMeasurement& i, const FeatureMeasurement& j) {
    return reused(reprojection_factors_, reprojections, i, j);
  };
  auto rsReprojection = [&](const FeatureMeasurement& i, const FeatureMeasurement& j) {
    return reused(rs_reprojection_factors_, rs_reprojections, i, j);
  };
  double* readout = state.readout;
  const ceres::CauchyLoss cauchy(model_.cauchy_loss_sigma);

  // The wheel intervals covered by readings (none unless [wheel] enable).
  WindowWheels& wheels = state.wheels;
  std::vector<std::pair<std::size_t, WheelPreintegration>> wheel_intervals;
  if (model_.wheel.enable)
    for (std::size_t k = 1; k < window.size(); ++k)
      if (auto pre = wheels.interval(window[k - 1], window[k], model_.wheel)) {
        // Checked against what the IMU and vision made of the interval so far.
        if (wheels.check(*pre, window[k - 1].pose, window[k].pose, window[k - 1].t, window[k].t,
                         model_.wheel) == WheelVerdict::Consistent)
          wheel_intervals.emplace_back(k, std::move(*pre));
        else
          ++wheels.factors_gated;
      }
  // The scales are variables while a wheel factor or the marginalisation prior holds them.
  const bool wheel_scales =
      model_.wheel.enable && model_.wheel.estimate_scale &&
      (!wheel_intervals.empty() || (state.prior && !wheels.scale_prior_pending));

  for (auto& s : window) {
    solver.addFrameBlock(s.pose, 7);
    solver.addFrameBlock(s.sb, 9);
  }
  // The online calibration likewise (constants when not estimated).
  const WheelOptions& wo = model_.wheel;
  const bool wheel_calib =
      wo.enable && wo.calibrating() &&
      (!wheel_intervals.empty() || (state.prior && !wheels.calib_prior_pending));
  if (model_.estimate_time_offset) solver.addFrameBlock(td, 1);
  if (model_.estimate_readout) solver.addFrameBlock(readout, 1);
  if (wheel_scales) {
    solver.addFrameBlock(wheels.scale_v, 1);
    solver.addFrameBlock(wheels.scale_w, 1);
  }
  if (wheel_calib && wo.estimate_extrinsic_yaw) solver.addFrameBlock(wheels.extrinsic_yaw, 1);
  if (wheel_calib && wo.estimate_time_offset) solver.addFrameBlock(wheels.time_offset, 1);
  if (state.prior) solver.addPrior(state.prior);
  // Gauge: hold position and yaw of the oldest pose (the prior carries no information on them).
  add(new GaugePrior(window.front().pose, kGaugeStiffness), nullptr, {window.front().pose});
  if (state.start_prior.active) {
    add(new SpeedBiasPrior(state.start_prior.mean, state.start_prior.sigma), nullptr,
        {window.front().sb});
    // The time offset is unobservable under uniform motion: anchor it to the configured value
    // until the marginalisation prior carries that information.
    if (model_.estimate_time_offset)
      add(new ScalarPrior(model_.time_offset_prior_mean_s, model_.time_offset_prior_sigma_s),
          nullptr, {td});
    // The readout likewise (unobservable without rotation or motion towards the features).
    if (model_.estimate_readout)
      add(new ScalarPrior(state.readout_prior_mean_s, model_.readout_prior_sigma_s), nullptr,
          {readout});
  }
  for (size_t k = 1; k < window.size(); ++k) {
    WindowSlot& a = window[k - 1];
    WindowSlot& b = window[k];
    if (b.preint->needsRepropagation(a.ba(), a.bg(), opt_.repropagate_acc_bias_m_s2,
                                     opt_.repropagate_gyr_bias_rad_s)) {
      b.preint->repropagate(a.ba(), a.bg());
    }
    add(new imu::ImuFactor(b.preint.get(), model_.g_world), nullptr, {a.pose, a.sb, b.pose, b.sb});
  }
  for (const auto& [k, pre] : wheel_intervals) {
    WheelTerm term = wheels.factor(pre, window[k - 1].pose, window[k].pose, wo);
    factors.push_back(std::move(term.cost));
    solver.addResidual(factors.back().get(), nullptr, term.blocks);
  }
  if (model_.wheel.enable && model_.wheel.ground_plane_sigma_m > 0.0) {
    // The flat floor, for the frames the gate found on it (window_ground_plane.h).
    const WheelOptions& w = model_.wheel;
    for (auto& s : window) {
      if (!s.ground_z) {
        ++wheels.ground_plane_gated;
        continue;
      }
      ++wheels.ground_plane_used;
      add(new GroundPlaneFactor(*s.ground_z, w.ground_plane_sigma_m, w.ground_plane_tilt_sigma_rad,
                                w.T_body_wheel),
          nullptr, {s.pose});
    }
  }
  if (wheel_scales && wheels.scale_prior_pending) {
    add(new ScalarPrior(wheels.prior_mean_v, model_.wheel.scale_prior_sigma), nullptr,
        {wheels.scale_v});
    add(new ScalarPrior(wheels.prior_mean_w, model_.wheel.scale_prior_sigma), nullptr,
        {wheels.scale_w});
  }
  if (wheel_calib && wheels.calib_prior_pending) {
    if (wo.estimate_extrinsic_yaw)
      add(new ScalarPrior(wheels.prior_mean_yaw, wo.extrinsic_yaw_prior_sigma_rad), nullptr,
          {wheels.extrinsic_yaw});
    if (wo.estimate_time_offset)
      add(new ScalarPrior(wheels.prior_mean_td, wo.time_offset_prior_sigma_s), nullptr,
          {wheels.time_offset});
  }
  const int newest = static_cast<int>(window.size()) - 1;
  WindowUpdate update;
  update.n_wheel_factors = static_cast<int>(wheel_intervals.size());
  // The inverse depths are solved in one buffer filled in track-id order (the solver's order
  // is the order of addition: the same bits whichever thread built the tracks).
  std::vector<FeatureTrack*> solved;
  for (auto& [id, f] : window.features().tracks())
    if (FeatureManager::usable(f, newest)) solved.push_back(&f);
  inv_depth_params_.assign(solved.size(), 0.0);
  for (std::size_t n = 0; n < solved.size(); ++n) {
    FeatureTrack& f = *solved[n];
    double* inv_depth = &inv_depth_params_[n];
    *inv_depth = f.inv_depth;
    ++update.n_features_used;
    const bool held = f.depthVerified() && model_.hold_verified_depth_constant;
    if (!held) solver.addEliminatedScalar(inv_depth, kMinInverseDepth);
    const int i = f.start_slot;
    for (size_t k = 1; k < f.obs.size(); ++k) {
      const int j = i + static_cast<int>(k);
      if (model_.estimate_readout)
        addResidual(rsReprojection(f.obs.front().meas, f.obs[k].meas), &cauchy,
                    {window[static_cast<size_t>(i)].pose, window[static_cast<size_t>(j)].pose,
                     inv_depth, td, readout});
      else
        addResidual(reprojection(f.obs.front().meas, f.obs[k].meas), &cauchy,
                    {window[static_cast<size_t>(i)].pose, window[static_cast<size_t>(j)].pose,
                     inv_depth, td});
    }
    if (f.depthVerified()) {
      ++update.n_depth_verified;
      if (!held)
        add(new ScalarPrior(f.verified_inv_depth, model_.depthPriorSigma(f)), nullptr, {inv_depth});
    }
  }

  WindowSolverOptions so;
  // One step when the second-newest frame's measurements leave the window after this update
  // (the window is solved fully again with the next keyframe); not without depth-verified
  // features, where the scale rests on the IMU alone (as for the function tolerance below).
  update.single_step = single_step && update.n_depth_verified > 0;
  so.max_iterations = update.single_step ? 1 : opt_.max_iterations;
  so.function_tolerance = update.n_depth_verified > 0 ? opt_.solver_function_tolerance
                                                      : opt_.solver_function_tolerance_no_depth;
  so.max_time_s = opt_.max_solver_time_s;
  update.summary = solver.solve(so);
  for (std::size_t n = 0; n < solved.size(); ++n) solved[n]->inv_depth = inv_depth_params_[n];
  for (auto& s : window) s.setPose(s.p(), s.q());  // keep quaternions exactly unit
  // The readout's bounds: a weakly excited estimate (straight driving) cannot run away.
  if (model_.estimate_readout) readout[0] = std::clamp(readout[0], 0.0, model_.readout_max_s);
  if (wheel_calib) wheels.clampCalibration(wo);
  return update;
}

}  // namespace rgbdi::estimator
