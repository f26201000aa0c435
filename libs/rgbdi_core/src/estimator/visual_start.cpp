#include "estimator/visual_start.h"

#include <vector>

#include "estimator/frame_window.h"
#include "rgbdi/estimator/scale_alignment.h"
#include "rgbdi/estimator/visual_sfm.h"
#include "rgbdi/imu/preintegration.h"

namespace rgbdi::estimator {

MovingStart solveVisualStart(FrameWindow& window, const EstimatorOptions& opt,
                             const ImuOptions& imu, const Eigen::Isometry3d& T_body_cam,
                             mrpt::system::COutputLogger& log) {
  if (static_cast<int>(window.size()) < opt.window_size)
    return MovingStart::failed("collecting frames for a visual (SfM) initialisation");
  std::vector<std::vector<frontend::FeatureObservation>> frames;
  std::vector<imu::Preintegration*> pre;
  for (auto& s : window) {
    frames.push_back(s.raw_features);
    pre.push_back(s.preint.get());
  }
  SfmOptions so;
  so.min_correspondences = opt.init_min_correspondences;
  so.min_parallax_norm = opt.init_min_parallax_px / EstimatorOptions::kVirtualFocalPx;
  so.reprojection_sigma_norm = opt.reprojection_sigma_px / EstimatorOptions::kVirtualFocalPx;
  so.seed = window.back().frame_index + 1;
  const auto sfm = solveVisualSfm(frames, so);
  if (!sfm) return MovingStart::failed("visual SfM over the window failed (parallax or tracks)");
  const auto align =
      alignWithScale(sfm->T_c0_c, T_body_cam, pre, imu.gravity_m_s2, opt.init_max_scale_rel_sigma);
  if (!align)
    return MovingStart::failed("scale/gravity alignment failed or the scale is not observable yet");
  MovingStart start;
  start.bg = window[1].preint->biasGyr();  // re-propagated with the solved bias
  if (start.bg.norm() > opt.fail_max_gyr_bias_rad_s)
    return MovingStart::failed("gyro bias above fail_max_gyr_bias_rad_s");
  const Eigen::Isometry3d T_cb = T_body_cam.inverse();
  for (const auto& T : sfm->T_c0_c) {
    Eigen::Isometry3d T_metric = T;
    T_metric.translation() *= align->scale;
    start.T_ref_body.push_back(T_metric * T_cb);
  }
  log.logFmt(mrpt::system::LVL_INFO,
             "visual initialisation: scale %.4f (predicted rel. sigma %.3f), %d points\n",
             align->scale, align->scale_rel_sigma, sfm->n_points);
  start.v_ref = align->v_ref;
  start.g_ref = align->g_ref;
  return start;
}

}  // namespace rgbdi::estimator
