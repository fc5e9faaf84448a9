#pragma once
// Counters of the depth completion nodelet, reported through diagnostic_updater: input and output
// rates over the last report period, latency, and every dropped or rejected message by reason.
#include <diagnostic_updater/diagnostic_updater.h>
#include <array>
#include <atomic>
#include <limits>
#include <memory>
#include <string>

#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/ros/conversions.hpp"
#include "multimodal_nvs/ros/frame_synchronizer.hpp"
#include "periodic_diagnostics.hpp"
#include "windowed_counters.hpp"

namespace multimodal_nvs {

class DepthCompletionDiagnostics {
 public:
  void start(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const std::string& node_name);

  // Thread-safe: called from subscriber and frame callbacks.
  void countInput(FrameInput input);
  void countSet();
  void countFault(ros_conversions::InputFault fault);
  /// A published depth map: its latency and compute time, and (ground_gp, image_guided) the
  /// ground plane it used, reported as the latest frame's.
  void countPublished(double latency_ms, const DepthMapStats& stats);
  /// Simulated time or the input stamps went back (a bag restarted): the node started over.
  void countTimeJump();
  /// A cloud larger than max_points was read every `step`-th point (processed, not rejected).
  void countSubsampled(std::size_t step);
  void setSubscribed(bool subscribed);

 private:
  void report(diagnostic_updater::DiagnosticStatusWrapper& status);

  /// inputs[] index of the synchronized sets, after the three FrameInputs.
  static constexpr int kSet = 3;

  struct Counts {
    std::array<unsigned long, kSet + 1> inputs{};
    unsigned long published = 0;
    std::array<unsigned long, ros_conversions::kInputFaultCount> faults{};
    double latency_sum_ms = 0.0, latency_max_ms = 0.0, compute_sum_ms = 0.0;
    unsigned long time_jumps = 0, subsampled = 0;
    std::size_t max_subsample_step = 0;
    /// The latest published frame's ground plane (empty source: no model with a ground plane).
    std::string ground_source;
    double ground_camera_height = -1.0, ground_pitch_deg = 0.0, ground_roll_deg = 0.0;
    /// The latest image_guided frame's return density and prior weight (-1: another model).
    double guided_return_density = -1.0, guided_prior_weight = -1.0;
    /// The latest image_guided frame's band top (NaN: the prior weighed the same everywhere).
    double guided_band_top_deg = std::numeric_limits<double>::quiet_NaN();
  };

  WindowedCounters<Counts> counters_;
  std::atomic<bool> subscribed_{false};
  PeriodicDiagnostics publisher_;
};

}  // namespace multimodal_nvs
