#include "estimator/window_marginalisation.h"

#include <ceres/ceres.h>

#include <set>
#include <unordered_map>

#include "estimator/window_state.h"
#include "rgbdi/estimator/ground_plane_factor.h"
#include "rgbdi/estimator/reprojection_factor.h"
#include "rgbdi/estimator/rolling_shutter_reprojection_factor.h"
#include "rgbdi/estimator/scalar_prior.h"
#include "rgbdi/estimator/speed_bias_prior.h"
#include "rgbdi/imu/imu_factor.h"

namespace rgbdi::estimator {

namespace {

/// Blocks that are no variables of the marginalisation.
std::set<const double*> constantBlocks(WindowState& state, const WindowCostModel& model) {
  std::set<const double*> constant;
  if (!model.estimate_time_offset) constant.insert(state.time_offset);
  if (!model.wheel.estimate_scale) {
    constant.insert(state.wheels.scale_v);
    constant.insert(state.wheels.scale_w);
  }
  if (!model.wheel.estimate_extrinsic_yaw) constant.insert(state.wheels.extrinsic_yaw);
  if (!model.wheel.estimate_time_offset) constant.insert(state.wheels.time_offset);
  return constant;
}

bool priorTouches(const WindowState& state, const double* block) {
  if (!state.prior) return false;
  for (const double* b : state.prior->keptBlocks())
    if (b == block) return true;
  return false;
}

}  // namespace

KeyframeState marginaliseOldestSlot(WindowState& state, const WindowCostModel& model, int segment) {
  FrameWindow& window = state.frames;
  std::set<const double*> constant = constantBlocks(state, model);
  const size_t N = window.size() - 1;  // index of the newest slot
  // Marginalise the oldest keyframe with everything that observes it.
  auto info = std::make_shared<MarginalizationInfo>();
  WindowSlot& s0 = window[0];
  std::set<const double*> remove{s0.pose, s0.sb};
  if (state.prior && (priorTouches(state, s0.pose) || priorTouches(state, s0.sb))) {
    info->add(
        {std::make_shared<MarginalizationFactor>(state.prior), nullptr, state.prior->keptBlocks()});
  }
  if (state.start_prior.active) {
    info->add({std::make_shared<SpeedBiasPrior>(state.start_prior.mean, state.start_prior.sigma),
               nullptr,
               {s0.sb}});
    if (model.estimate_time_offset)
      info->add({std::make_shared<ScalarPrior>(model.time_offset_prior_mean_s,
                                               model.time_offset_prior_sigma_s),
                 nullptr,
                 {state.time_offset}});
    if (model.estimate_readout)
      info->add(
          {std::make_shared<ScalarPrior>(state.readout_prior_mean_s, model.readout_prior_sigma_s),
           nullptr,
           {state.readout}});
    state.start_prior.active = false;  // from now on it lives inside the marginalisation prior
  }
  info->add({std::make_shared<imu::ImuFactor>(window[1].preint.get(), model.g_world),
             nullptr,
             {s0.pose, s0.sb, window[1].pose, window[1].sb}});
  // What the wheels told the window about this interval stays in the prior.
  WindowWheels& wheels = state.wheels;
  if (model.wheel.enable) {
    auto pre = wheels.interval(s0, window[1], model.wheel);
    const WheelVerdict verdict =
        pre ? wheels.check(*pre, s0.pose, window[1].pose, s0.t, window[1].t, model.wheel)
            : WheelVerdict::Consistent;
    if (pre) wheels.count(verdict, s0.t, window[1].t);
    if (pre && verdict == WheelVerdict::Consistent) {
      const WheelOptions& wo = model.wheel;
      WheelTerm term = wheels.factor(*pre, s0.pose, window[1].pose, wo);
      info->add({std::move(term.cost), nullptr, std::move(term.blocks)});
      if (wo.calibrating() && wheels.calib_prior_pending) {
        if (wo.estimate_extrinsic_yaw)
          info->add({std::make_shared<ScalarPrior>(wheels.prior_mean_yaw,
                                                   wo.extrinsic_yaw_prior_sigma_rad),
                     nullptr,
                     {wheels.extrinsic_yaw}});
        if (wo.estimate_time_offset)
          info->add(
              {std::make_shared<ScalarPrior>(wheels.prior_mean_td, wo.time_offset_prior_sigma_s),
               nullptr,
               {wheels.time_offset}});
        wheels.calib_prior_pending = false;
      }
      if (model.wheel.estimate_scale && wheels.scale_prior_pending) {
        info->add(
            {std::make_shared<ScalarPrior>(wheels.prior_mean_v, model.wheel.scale_prior_sigma),
             nullptr,
             {wheels.scale_v}});
        info->add(
            {std::make_shared<ScalarPrior>(wheels.prior_mean_w, model.wheel.scale_prior_sigma),
             nullptr,
             {wheels.scale_w}});
        wheels.scale_prior_pending = false;
      }
    } else if (!pre) {
      ++wheels.intervals_gap;
    }
    // ... and what the floor told it about the leaving frame.
    if (model.wheel.ground_plane_sigma_m > 0.0 && s0.ground_z)
      info->add({std::make_shared<GroundPlaneFactor>(*s0.ground_z, model.wheel.ground_plane_sigma_m,
                                                     model.wheel.ground_plane_tilt_sigma_rad,
                                                     model.wheel.T_body_wheel),
                 nullptr,
                 {s0.pose}});
  }
  auto loss = std::make_shared<ceres::CauchyLoss>(model.cauchy_loss_sigma);
  const int newest = static_cast<int>(N);
  for (auto& [id, f] : window.features().tracks()) {
    if (f.start_slot != 0 || !FeatureManager::usable(f, newest)) continue;
    for (size_t k = 1; k < f.obs.size(); ++k) {
      if (model.estimate_readout) {
        info->add(
            {std::make_shared<RollingShutterReprojectionFactor>(
                 f.obs.front().meas, f.obs[k].meas, model.T_body_cam, model.reprojection_sqrt_info),
             loss,
             {s0.pose, window[k].pose, &f.inv_depth, state.time_offset, state.readout}});
        continue;
      }
      info->add(
          {std::make_shared<ReprojectionFactor>(f.obs.front().meas, f.obs[k].meas, model.T_body_cam,
                                                model.reprojection_sqrt_info),
           loss,
           {s0.pose, window[k].pose, &f.inv_depth, state.time_offset}});
    }
    // Depth-verified features held constant are not variables: nothing to marginalise.
    if (f.depthVerified() && model.hold_verified_depth_constant) {
      constant.insert(&f.inv_depth);
    } else {
      remove.insert(&f.inv_depth);
      if (f.depthVerified()) {
        info->add({std::make_shared<ScalarPrior>(f.verified_inv_depth, model.depthPriorSigma(f)),
                   nullptr,
                   {&f.inv_depth}});
      }
    }
  }
  const bool kept = info->marginalize(remove, constant);
  const KeyframeState leaving{s0.t, s0.T(), s0.frame_index, segment, s0.bridged_s};
  // The slots move down by one: the prior follows its blocks to their new addresses.
  std::unordered_map<const double*, double*> remap;
  for (size_t k = 1; k <= N; ++k) {
    remap[window[k].pose] = window[k - 1].pose;
    remap[window[k].sb] = window[k - 1].sb;
  }
  window.removeOldest(model.T_body_cam);
  if (kept) {
    info->remapBlocks(remap);
    state.prior = info;
  } else {
    state.prior.reset();
    wheels.priorDropped();
  }
  if (model.wheel.enable) wheels.trimBefore(window.front().t, model.wheel);
  return leaving;
}

void dropSecondNewestSlot(WindowState& state, const WindowCostModel& model) {
  FrameWindow& window = state.frames;
  const size_t N = window.size() - 1;  // index of the newest slot
  // Drop its visual measurements, merge its IMU interval into the next one, and remove its pose
  // from the prior if the prior holds it.
  WindowSlot& s1 = window[N - 1];
  if (state.prior && priorTouches(state, s1.pose)) {
    auto info = std::make_shared<MarginalizationInfo>();
    info->add(
        {std::make_shared<MarginalizationFactor>(state.prior), nullptr, state.prior->keptBlocks()});
    if (info->marginalize({s1.pose}, constantBlocks(state, model))) {
      state.prior = info;
    } else {
      state.prior.reset();
      state.wheels.priorDropped();
    }
  }
  std::unordered_map<const double*, double*> remap;
  remap[window[N].pose] = window[N - 1].pose;
  remap[window[N].sb] = window[N - 1].sb;
  window.dropSecondNewest();
  if (state.prior) state.prior->remapBlocks(remap);
}

}  // namespace rgbdi::estimator
