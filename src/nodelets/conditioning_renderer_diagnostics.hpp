#pragma once
// Counters of the conditioning renderer nodelet, reported through diagnostic_updater: input and
// output rates over the last report period, render and per-frame times, keyframes, bursts, and
// every rejected input set by reason.
#include <diagnostic_updater/diagnostic_updater.h>
#include <array>
#include <atomic>
#include <memory>
#include <string>

#include "multimodal_nvs/ros/renderer_conversions.hpp"
#include "periodic_diagnostics.hpp"
#include "windowed_counters.hpp"

namespace multimodal_nvs {

class ConditioningRendererDiagnostics {
 public:
  void start(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const std::string& node_name);

  // Thread-safe: called from subscriber, frame and service callbacks.
  void countSet();
  void countCameraImage();
  /// A camera image the live-view thread never saw (its queue was full).
  void countCameraImageDropped();
  /// Camera images recorded but not rendered: newer ones were waiting.
  void countLiveSkipped(int frames);
  void countFault(ros_conversions::RendererFault fault);
  /// One frame rendered and published: splatting time, and the whole callback (conversion, tf,
  /// splatting, preview, publishing).
  void countFrame(double render_ms, double frame_ms);
  void countKeyframe(std::size_t points, double cloud_ms);
  void countBurst(int frames, double burst_ms);
  /// How a recorded-trajectory export ended.
  enum class ExportEnd { kComplete, kAborted, kCancelled, kFailed };
  void countExport(ExportEnd end, int frames, double ms);
  void setSubscribed(bool subscribed);

 private:
  void report(diagnostic_updater::DiagnosticStatusWrapper& status);

  struct Counts {
    unsigned long sets = 0, camera_images = 0, camera_images_dropped = 0, live_skipped = 0,
                  frames = 0, keyframes = 0, bursts = 0, burst_frames = 0;
    // Recorded-trajectory exports by how they ended (ExportEnd).
    std::array<unsigned long, 4> exports{};
    double export_sum_ms = 0.0;
    std::array<unsigned long, ros_conversions::kRendererFaultCount> faults{};
    double render_sum_ms = 0.0, render_max_ms = 0.0, frame_sum_ms = 0.0, burst_sum_ms = 0.0;
    // The latest keyframe's, not a sum: the totals' copy is reported.
    std::size_t keyframe_points = 0;
    double keyframe_cloud_ms = 0.0;
  };

  WindowedCounters<Counts> counters_;
  std::atomic<bool> subscribed_{false};
  PeriodicDiagnostics publisher_;
};

}  // namespace multimodal_nvs
