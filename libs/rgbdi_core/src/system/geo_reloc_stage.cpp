#include "rgbdi/system/geo_reloc_stage.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "rgbdi/reloc/keyframe_samples.h"

namespace rgbdi::system {

GeoRelocStage::GeoRelocStage(const reloc::RelocOptions& options,
                             std::shared_ptr<const map::MapData> map,
                             const Eigen::Isometry3d& T_body_cam, bool threaded, bool live)
    : options_(options),
      map_(std::move(map)),
      T_body_cam_(T_body_cam),
      live_(live),
      confirm_(options) {
  worker_ = std::make_unique<StageWorker<reloc::RelocJob>>(
      "geometric relocalisation", [this](reloc::RelocJob& j) { handle(j); }, threaded, 4);
}

GeoRelocStage::~GeoRelocStage() = default;

void GeoRelocStage::finish() { worker_->finish(); }

bool GeoRelocStage::takeTrackingAtEnd(loop::LoopCloser& closer) {
  bool solved = false;
  for (const Pending& p : pending_) {
    worker_->waitHandled(p.job);
    reloc::RelocFit fit;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      fit = std::move(results_[p.job - 1]);
      results_[p.job - 1] = reloc::RelocFit();
    }
    if (fit.track && takeTrack(fit, closer)) solved = true;
  }
  pending_.clear();
  return solved;
}

GeoRelocReport GeoRelocStage::report() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return report_;
}

void GeoRelocStage::handle(reloc::RelocJob& job) {
  if (!relocaliser_) {
    // The map's plan is built here, on this thread, at the first attempt.
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<reloc::DepthSample> samples;
    for (const loop::LoopKeyframe& k : map_->places)
      reloc::appendDepthSamples(k, k.T_world_body, map_->manifest.camera, T_body_cam_, &samples);
    relocaliser_ = std::make_unique<reloc::GeometricRelocaliser>(samples, options_);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::lock_guard<std::mutex> lock(mutex_);
    report_.map_build_ms = ms;
  }
  reloc::RelocFit fit = job.track ? relocaliser_->track(job) : relocaliser_->fit(job);
  std::lock_guard<std::mutex> lock(mutex_);
  if (job.track) {
    report_.track_ms_total += fit.ms;
    report_.track_ms_max = std::max(report_.track_ms_max, fit.ms);
  } else {
    ++report_.searched;
    report_.ms_total += fit.ms;
    report_.ms_max = std::max(report_.ms_max, fit.ms);
  }
  if (results_.size() < job.number) results_.resize(job.number);
  results_[job.number - 1] = std::move(fit);
}

reloc::RelocJob GeoRelocStage::makeJob(const loop::LoopCloser& closer, const PinholeCamera& cam,
                                       bool track) const {
  const std::vector<loop::LoopKeyframe>& kfs = closer.keyframes();
  const loop::LoopKeyframe& newest = kfs.back();
  reloc::RelocJob j;
  j.segment = newest.segment;
  j.anchor_id = newest.id;
  j.T_anchor = closer.pose(newest.id);
  j.travelled_m = newest.travelled_m;
  j.t_query = newest.t - closer.timeShift();
  // Newest first, up to the longest path a submap may need (GeometricRelocaliser picks).
  // Tracking: only the submap ICP uses (no search, no longer path for more structure).
  const double max_path =
      track ? options_.submap_path_m : std::max(options_.submap_path_m, options_.submap_max_path_m);
  j.track = track;
  for (auto it = kfs.rbegin(); it != kfs.rend() && it->segment == newest.segment; ++it) {
    const double path = newest.travelled_m - it->travelled_m;
    if (path > max_path) break;
    const Eigen::Isometry3d T = closer.pose(it->id);
    reloc::appendDepthSamples(*it, T, cam, T_body_cam_, &j.samples);
    j.spans.push_back({path, j.samples.size()});
    if (track && j.part_poses.size() < static_cast<std::size_t>(options_.track_keyframes))
      j.part_poses.emplace_back(it->id, T);
  }
  return j;
}

bool GeoRelocStage::takeTrack(const reloc::RelocFit& fit, loop::LoopCloser& closer) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    GeoRelocReport& r = report_;
    ++r.track_results;
    if (fit.outcome == reloc::FitOutcome::kFit) {
      ++r.track_fits;
      r.track_correction_max_m = std::max(r.track_correction_max_m, fit.correction_m);
    } else if (fit.outcome == reloc::FitOutcome::kTooFar) {
      ++r.track_too_far;
    } else if (fit.outcome == reloc::FitOutcome::kUnrefined) {
      ++r.track_unrefined;
    } else {
      ++r.track_too_little;
    }
  }
  if (fit.outcome != reloc::FitOutcome::kFit) return false;
  // Where the fit puts the keyframes: the correction applied to their poses at the job's
  // keyframe (the graph may have been solved since: the edges carry the fit's own relation).
  std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>> placed;
  for (const auto& [id, T] : fit.part_poses) placed.emplace_back(id, fit.T_map_part * T);
  return closer
      .trackByAlignment(fit.segment, placed, options_.join_max_distance_m,
                        options_.track_sigma_pos_m, options_.track_sigma_yaw_deg * M_PI / 180.0)
      .solved;
}

bool GeoRelocStage::afterKeyframe(loop::LoopCloser& closer, const PinholeCamera& cam) {
  ++keyframes_;
  const loop::LoopKeyframe& newest = closer.keyframes().back();
  if (newest.segment != segment_) {
    segment_ = newest.segment;
    last_attempt_travelled_ = -1e300;
    last_track_travelled_ = -1e300;
  }
  bool solved = false;
  // Results due now (offline: wait for them; live: only those ready).
  while (!pending_.empty() && pending_.front().due <= keyframes_) {
    const Pending p = pending_.front();
    if (live_) {
      if (worker_->handled() < p.job) break;
    } else {
      worker_->waitHandled(p.job);
    }
    pending_.pop_front();
    reloc::RelocFit fit;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      fit = results_[p.job - 1];
      results_[p.job - 1] = reloc::RelocFit();  // taken: free its memory
    }
    if (fit.track) {
      if (takeTrack(fit, closer)) solved = true;
      continue;
    }
    if (closer.connectedToOrigin(fit.segment)) continue;  // placed meanwhile (visually)
    taken_.push_back(fit);
    const auto confirmed = confirm_.add(fit, closer.pose(newest.id).translation(),
                                        [&closer](std::uint64_t id) { return closer.pose(id); });
    {
      std::lock_guard<std::mutex> lock(mutex_);
      GeoRelocReport& r = report_;
      ++r.results;
      switch (fit.outcome) {
        case reloc::FitOutcome::kTooLittle:
          ++r.too_little;
          break;
        case reloc::FitOutcome::kNoPlace:
          ++r.no_place;
          break;
        case reloc::FitOutcome::kAmbiguous:
          ++r.ambiguous;
          break;
        case reloc::FitOutcome::kNoHeight:
          ++r.no_height;
          break;
        case reloc::FitOutcome::kUnrefined:
          ++r.unrefined;
          break;
        case reloc::FitOutcome::kFit:
          ++r.fits;
          break;
        case reloc::FitOutcome::kTooFar:  // tracking only
          break;
      }
      r.disagreements = static_cast<std::uint64_t>(confirm_.disagreements());
      r.last_outcome = reloc::toString(fit.outcome);
      r.last_places = fit.places;
      r.last_candidates = fit.candidates;
      r.max_places = std::max(r.max_places, fit.places);
      if (confirmed) ++r.confirmed;
    }
    if (!confirmed) continue;
    // Outside the lock: the solve takes a while, and report() must stay quick.
    const loop::LoopUpdate u =
        closer.joinByAlignment(fit.segment, *confirmed, options_.join_keyframes,
                               options_.join_max_distance_m, newest.t - closer.timeShift());
    if (u.solved) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        ++report_.joined;
      }
      solved = true;
      pending_.clear();                            // the part is placed: later attempts are moot
      last_track_travelled_ = newest.travelled_m;  // tracking from track_interval_m on
    }
  }
  const bool busy = live_ && worker_->handled() < worker_->submitted();
  // A job for the stage's thread, its result taken result_lag_keyframes later.
  const auto submit = [&](bool track, std::uint64_t& counter) {
    reloc::RelocJob job = makeJob(closer, cam, track);
    job.number = ++jobs_;
    pending_.push_back(
        {job.number, keyframes_ + static_cast<std::uint64_t>(options_.result_lag_keyframes)});
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++counter;
    }
    worker_->submit(std::move(job));
  };
  // Tracking while the part is in the map's frame.
  if (closer.connectedToOrigin(newest.segment) && options_.track_interval_m > 0.0 &&
      newest.travelled_m - last_track_travelled_ >= options_.track_interval_m && !busy) {
    last_track_travelled_ = newest.travelled_m;
    submit(true, report_.track_attempts);
  }
  // A new attempt while the part is not placed.
  if (!closer.connectedToOrigin(newest.segment) &&
      newest.travelled_m - last_attempt_travelled_ >= options_.attempt_interval_m && !busy) {
    last_attempt_travelled_ = newest.travelled_m;
    submit(false, report_.attempts);
  }
  return solved;
}

}  // namespace rgbdi::system
