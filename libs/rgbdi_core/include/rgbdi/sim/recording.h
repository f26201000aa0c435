// A real recording of an IMU with the ground truth of its body (IMU) frame: what a hybrid
// sequence (`rgbdi-sim --profile recorded`) replays. Samples are kept exactly as the files hold
// them: stamps in the recording's own clock (seconds), IMU values in the body = IMU frame.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <stdexcept>
#include <string>
#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/sim/imu_synth.h"

namespace rgbdi::sim {

/// A malformed or missing recording file; the message names the file, the line and the fault.
class RecordingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One ground-truth sample of the body (IMU) frame.
struct RecordedPose {
  double t = 0.0;                                     ///< [s] recording clock (the IMU's)
  Eigen::Vector3d p_world = Eigen::Vector3d::Zero();  ///< [m]
  Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();  ///< unit
  bool has_velocity = false;                                         ///< v_world given
  Eigen::Vector3d v_world = Eigen::Vector3d::Zero();                 ///< [m/s]
  bool has_bias = false;                                             ///< bias given
  ImuBias bias;  ///< the reference's estimate of the IMU biases
};

/// The recording's IMU as its datasheet / calibration describes it (Kalibr convention).
struct RecordedImuSensor {
  std::string name;                ///< e.g. "ADIS16448 (EuRoC MAV)"
  double rate_hz = 0.0;            ///< [Hz] nominal
  double gyr_noise_density = 0.0;  ///< [rad/s/sqrt(Hz)]
  double gyr_random_walk = 0.0;    ///< [rad/s^2/sqrt(Hz)]
  double acc_noise_density = 0.0;  ///< [m/s^2/sqrt(Hz)]
  double acc_random_walk = 0.0;    ///< [m/s^3/sqrt(Hz)]
  double gravity_m_s2 = 9.81;      ///< [m/s^2] of the ground truth's world (z up)
};

struct Recording {
  std::string format;                      ///< one of recordingFormats()
  std::string directory;                   ///< where it was read from
  std::vector<ImuSample> imu;              ///< strictly increasing stamps
  std::vector<RecordedPose> ground_truth;  ///< strictly increasing stamps
  RecordedImuSensor sensor;
  /// The dataset's camera in the body frame (default of [extrinsic] for this recording).
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
};

/// "euroc" (EuRoC MAV / ASL CSV).
const std::vector<std::string>& recordingFormats();

/// Reads the recording in `dir` in the given format. Throws RecordingError (file, line, fault)
/// and std::invalid_argument for an unknown format.
Recording readRecording(const std::string& dir, const std::string& format);

/// EuRoC ASL: DIR/imu0.csv and DIR/groundtruth.csv, or the dataset's own layout
/// DIR[/mav0]/imu0/data.csv and DIR[/mav0]/state_groundtruth_estimate0/data.csv. IMU rows:
/// t [ns], w xyz [rad/s], a xyz [m/s^2]; ground-truth rows: t [ns], p xyz [m], q wxyz,
/// then optionally v xyz [m/s], bg xyz [rad/s], ba xyz [m/s^2]. Lines starting with '#' are
/// comments. In the dataset's layout, the IMU's rate and noise come from imu0/sensor.yaml and the
/// camera from cam0/sensor.yaml (T_BS) when they are there (an IMU T_BS must be the identity:
/// body = IMU); otherwise, and in the flat layout, the EuRoC MAV's ADIS16448 and cam0.
Recording readEurocRecording(const std::string& dir);

/// Seconds of an integer nanosecond stamp, rounded once (the whole seconds and the fraction
/// are converted separately so that no digit is lost before the final addition).
double nanosecondsToSeconds(long long ns);

}  // namespace rgbdi::sim
