// When a geometric fit is trusted: a fit (one distinct place, overlap and free space checked by
// the search) is only a proposal until confirm_fits fits in all (separate global searches on
// the growing local plan), the last started at least confirm_distance_m of path after the
// first, put the part at the same place (within confirm_max_disagreement_m / _deg where the
// part is now). A fit that disagrees with the proposal replaces it (a wrong place, e.g. the
// twin of two identical rooms that won one search, rarely holds still over several). An
// ambiguous attempt drops it too: the world still offers several places, so the proposal must
// be earned again by fits that follow (in the twin rooms, single fits on one twin came between
// long runs of ambiguous searches and were confirmed 7 s apart). Attempts that fail for other
// reasons (too little structure, refused by ICP) leave it waiting.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "rgbdi/reloc/geometric_relocaliser.h"
#include "rgbdi/reloc/reloc_options.h"

namespace rgbdi::reloc {

class FitConfirmation {
 public:
  explicit FitConfirmation(const RelocOptions& options) : options_(options) {}
  /// Takes the next attempt of the part (segment changes start over). `T_anchor_now`: the
  /// current pose (part frame) of each fit's anchor keyframe is asked through `anchorPose`, so
  /// that corrections of the part's own poses since the attempt are followed. Returns the
  /// confirmed alignment (part frame now -> map frame) when this fit confirms the proposal.
  template <class AnchorPose>
  std::optional<Eigen::Isometry3d> add(const RelocFit& fit, const Eigen::Vector3d& p_part_now,
                                       AnchorPose anchorPose) {
    if (proposal_ && proposal_->segment != fit.segment) proposal_.reset();
    last_outcome_ = fit.outcome;
    if (fit.outcome == FitOutcome::kAmbiguous) proposal_.reset();
    if (fit.outcome != FitOutcome::kFit) return std::nullopt;
    const Eigen::Isometry3d A_new = alignmentNow(fit, anchorPose(fit.anchor_id));
    if (!proposal_) {
      proposal_ = fit;
      agreeing_ = 1;
      agreeing_fits_.assign(1, fit);
      return std::nullopt;
    }
    const Eigen::Isometry3d A_old = alignmentNow(*proposal_, anchorPose(proposal_->anchor_id));
    if (!agree(A_old, A_new, p_part_now)) {
      ++disagreements_;
      proposal_ = fit;
      agreeing_ = 1;
      agreeing_fits_.assign(1, fit);
      return std::nullopt;
    }
    ++agreeing_;
    agreeing_fits_.push_back(fit);
    if (agreeing_ < options_.confirm_fits ||
        fit.travelled_m - proposal_->travelled_m < options_.confirm_distance_m)
      return std::nullopt;  // agrees, but not enough yet: keep the older proposal
    proposal_.reset();
    if (!options_.confirm_join_mean) return A_new;
    std::vector<Eigen::Isometry3d> all;
    for (const RelocFit& f : agreeing_fits_)
      all.push_back(alignmentNow(f, anchorPose(f.anchor_id)));
    return mean(all);
  }
  /// The mean of yaw + translation alignments: mean translation, circular mean yaw.
  static Eigen::Isometry3d mean(const std::vector<Eigen::Isometry3d>& alignments);
  /// Two alignments agree at the part's position p (part frame).
  bool agree(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
             const Eigen::Vector3d& p) const;
  bool waiting() const { return proposal_.has_value(); }
  FitOutcome lastOutcome() const { return last_outcome_; }
  int disagreements() const { return disagreements_; }
  /// The fit's alignment for the part's poses as they are now: the anchor stays where the fit
  /// put it.
  static Eigen::Isometry3d alignmentNow(const RelocFit& fit,
                                        const Eigen::Isometry3d& T_anchor_now) {
    return fit.T_map_part * fit.T_anchor * T_anchor_now.inverse();
  }

 private:
  RelocOptions options_;
  std::optional<RelocFit> proposal_;
  int agreeing_ = 0;                     ///< fits agreeing with the proposal, itself included
  std::vector<RelocFit> agreeing_fits_;  ///< those fits
  FitOutcome last_outcome_ = FitOutcome::kTooLittle;
  int disagreements_ = 0;
};

}  // namespace rgbdi::reloc
