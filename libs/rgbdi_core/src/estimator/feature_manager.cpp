#include "rgbdi/estimator/feature_manager.h"

#include <Eigen/SVD>

namespace rgbdi::estimator {
namespace {

/// Pose of camera at `slot` in the world.
Eigen::Isometry3d worldCam(const SlotPoses& T_wb, int slot, const Eigen::Isometry3d& T_bc) {
  return T_wb[static_cast<size_t>(slot)] * T_bc;
}

/// Linear (DLT) triangulation of a track in its reference camera. Returns depth, or 0 on failure.
double triangulate(const FeatureTrack& f, const SlotPoses& T_wb, const Eigen::Isometry3d& T_bc) {
  const Eigen::Isometry3d T_w_ref = worldCam(T_wb, f.start_slot, T_bc);
  Eigen::MatrixXd A(2 * f.obs.size(), 4);
  for (size_t k = 0; k < f.obs.size(); ++k) {
    const Eigen::Isometry3d T_ck_ref =
        worldCam(T_wb, f.start_slot + static_cast<int>(k), T_bc).inverse() * T_w_ref;
    const Eigen::Matrix<double, 3, 4> P = T_ck_ref.matrix().topRows<3>();
    const Eigen::Vector3d& x = f.obs[k].meas.xn;
    A.row(2 * static_cast<Eigen::Index>(k)) = x.x() * P.row(2) - P.row(0);
    A.row(2 * static_cast<Eigen::Index>(k) + 1) = x.y() * P.row(2) - P.row(1);
  }
  const Eigen::Vector4d X =
      Eigen::JacobiSVD<Eigen::MatrixXd>(A, Eigen::ComputeThinV).matrixV().col(3);
  if (std::abs(X.w()) < 1e-12) return 0.0;
  return X.z() / X.w();
}

}  // namespace

FeatureManager::FrameLinks FeatureManager::addFrame(
    int slot, const std::vector<std::pair<std::uint64_t, TrackObservation>>& features,
    const Eigen::Matrix3d* R_c2_c1) {
  int tracked = 0;
  for (const auto& [id, o] : features) {
    auto it = tracks_.find(id);
    if (it != tracks_.end() && it->second.endSlot() == slot - 1) {
      it->second.obs.push_back(o);
      ++tracked;
      continue;
    }
    // New feature (or a track whose continuity was broken: start it again).
    FeatureTrack f;
    f.id = id;
    f.start_slot = slot;
    f.obs.push_back(o);
    tracks_[id] = std::move(f);
  }
  double sum = 0.0;
  int n = 0;
  for (const auto& [id, f] : tracks_) {
    if (f.start_slot <= slot - 2 && f.endSlot() >= slot - 1) {
      const auto& a = f.obs[static_cast<size_t>(slot - 2 - f.start_slot)].meas.xn;
      const auto& b = f.obs[static_cast<size_t>(slot - 1 - f.start_slot)].meas.xn;
      if (R_c2_c1) {
        const Eigen::Vector3d r = *R_c2_c1 * b;
        if (!(r.z() > 0.0)) continue;  // behind the other camera: no parallax to compare
        sum += (a.head<2>() - r.head<2>() / r.z()).norm();
      } else {
        sum += (a.head<2>() - b.head<2>()).norm();
      }
      ++n;
    }
  }
  FrameLinks links;
  links.parallax = n > 0 ? sum / n : 0.0;
  links.n_parallax = n;
  links.n_tracked = tracked;
  return links;
}

void FeatureManager::updateDepths(const SlotPoses& T_wb, const Eigen::Isometry3d& T_bc,
                                  const DepthCheckOptions& opt) {
  // Every slot's camera pose and its inverse, once per call (not once per observation pair).
  std::vector<Eigen::Isometry3d> T_wc(T_wb.size()), T_cw(T_wb.size());
  for (std::size_t s = 0; s < T_wb.size(); ++s) {
    T_wc[s] = worldCam(T_wb, static_cast<int>(s), T_bc);
    T_cw[s] = T_wc[s].inverse();
  }
  for (auto& [id, f] : tracks_) {
    if (f.obs.size() < 2) continue;
    const Eigen::Isometry3d& T_ref_w = T_cw[static_cast<std::size_t>(f.start_slot)];
    // Algorithm 1: every observation with depth is checked against every other observation.
    double sum = 0.0;
    int count = 0, n_obs = 0;
    for (size_t k = 0; k < f.obs.size(); ++k) {
      const double d = f.obs[k].depth_m;
      if (d < opt.min_depth_m || d > opt.max_depth_m) continue;
      const Eigen::Vector3d p_w =
          T_wc[static_cast<std::size_t>(f.start_slot) + k] * (f.obs[k].meas.xn * d);
      bool agreed = false;
      for (size_t l = 0; l < f.obs.size(); ++l) {
        if (l == k) continue;
        const Eigen::Vector3d p_l = T_cw[static_cast<std::size_t>(f.start_slot) + l] * p_w;
        if (p_l.z() <= 1e-6) continue;
        const double res = (p_l.head<2>() / p_l.z() - f.obs[l].meas.xn.head<2>()).norm();
        if (res < opt.tolerance_norm) {
          sum += (T_ref_w * p_w).z();
          ++count;
          agreed = true;
        }
      }
      n_obs += agreed ? 1 : 0;
    }
    if (count > 0) {
      const double mean = sum / count;
      if (mean >= opt.min_depth_m && mean <= opt.max_depth_m) {
        // Re-evaluated every frame: the mean over all agreeing observations so far (more
        // observations, less noise); it is held constant inside each optimisation.
        if (opt.hold_constant || f.source != DepthSource::kVerified) f.inv_depth = 1.0 / mean;
        f.verified_inv_depth = 1.0 / mean;
        f.verified_observations = n_obs;
        f.source = DepthSource::kVerified;
        continue;
      }
    }
    if (f.source == DepthSource::kVerified) f.source = DepthSource::kTriangulated;
    if (f.source == DepthSource::kTriangulated) continue;  // keep the optimised estimate
    const double z = triangulate(f, T_wb, T_bc);
    if (z > opt.min_triangulation_depth_m) {
      f.inv_depth = 1.0 / z;
      f.source = DepthSource::kTriangulated;
    } else if (f.obs.front().depth_m > opt.min_depth_m) {
      // No parallax yet: start from the sensor depth, free to move.
      f.inv_depth = 1.0 / f.obs.front().depth_m;
      f.source = DepthSource::kTriangulated;
    }
  }
}

void FeatureManager::removeOldest(const SlotPoses& T_wb, const Eigen::Isometry3d& T_bc) {
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    FeatureTrack& f = it->second;
    if (f.start_slot != 0) {
      --f.start_slot;
      ++it;
      continue;
    }
    if (f.obs.size() < 3) {  // would be left with fewer than 2 observations
      it = tracks_.erase(it);
      continue;
    }
    if (f.hasDepth()) {
      const Eigen::Vector3d p_w = worldCam(T_wb, 0, T_bc) * (f.obs.front().meas.xn / f.inv_depth);
      const Eigen::Vector3d p_new = worldCam(T_wb, 1, T_bc).inverse() * p_w;
      if (p_new.z() > 1e-3) {
        f.inv_depth = 1.0 / p_new.z();
        // The reference frame changed: the depth must be verified again for the new one.
        f.source = DepthSource::kTriangulated;
      } else {
        f.inv_depth = 0.0;
        f.source = DepthSource::kNone;
      }
    }
    f.obs.erase(f.obs.begin());
    ++it;
  }
}

void FeatureManager::removeSlot(int slot) {
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    FeatureTrack& f = it->second;
    if (f.start_slot > slot) {
      --f.start_slot;
    } else if (f.start_slot == slot) {
      f.obs.erase(f.obs.begin());
      f.inv_depth = 0.0;
      f.source = DepthSource::kNone;
      if (f.obs.empty()) {
        it = tracks_.erase(it);
        continue;
      }
    } else if (f.endSlot() >= slot) {
      f.obs.erase(f.obs.begin() + (slot - f.start_slot));
    }
    ++it;
  }
}

void FeatureManager::removeOutliers() {
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    if (it->second.outlier) {
      it = tracks_.erase(it);
    } else {
      ++it;
    }
  }
}

bool FeatureManager::usable(const FeatureTrack& f, int newest_slot) {
  if (f.outlier || f.obs.size() < 2 || !f.hasDepth()) return false;
  return f.depthVerified() || f.start_slot < newest_slot - 1;
}

int FeatureManager::countUsable(int newest_slot) const {
  int n = 0;
  for (const auto& [id, f] : tracks_) n += usable(f, newest_slot) ? 1 : 0;
  return n;
}

}  // namespace rgbdi::estimator
