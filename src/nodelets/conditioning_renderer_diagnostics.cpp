#include "conditioning_renderer_diagnostics.hpp"

#include <algorithm>

namespace multimodal_nvs {

namespace rc = ros_conversions;

void ConditioningRendererDiagnostics::start(ros::NodeHandle& nh, ros::NodeHandle& private_nh,
                                            const std::string& node_name) {
  window_start_ = ros::WallTime::now();
  publisher_.start(nh, private_nh, node_name, "conditioning renderer",
                   [this](diagnostic_updater::DiagnosticStatusWrapper& status) { report(status); });
}

void ConditioningRendererDiagnostics::countSet() {
  std::lock_guard<std::mutex> lock(mutex_);
  ++window_.sets;
  ++total_.sets;
}

void ConditioningRendererDiagnostics::countFault(rc::RendererFault fault) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++window_.faults[static_cast<int>(fault)];
  ++total_.faults[static_cast<int>(fault)];
}

void ConditioningRendererDiagnostics::countFrame(double render_ms, double frame_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (Counts* counts : {&window_, &total_}) {
    ++counts->frames;
    counts->render_sum_ms += render_ms;
    counts->render_max_ms = std::max(counts->render_max_ms, render_ms);
    counts->frame_sum_ms += frame_ms;
  }
}

void ConditioningRendererDiagnostics::countKeyframe(std::size_t points, double cloud_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++window_.keyframes;
  ++total_.keyframes;
  keyframe_points_ = points;
  keyframe_cloud_ms_ = cloud_ms;
}

void ConditioningRendererDiagnostics::countBurst(int frames, double burst_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (Counts* counts : {&window_, &total_}) {
    ++counts->bursts;
    counts->burst_frames += static_cast<unsigned long>(frames);
    counts->burst_sum_ms += burst_ms;
  }
}

void ConditioningRendererDiagnostics::setSubscribed(bool subscribed) {
  std::lock_guard<std::mutex> lock(mutex_);
  subscribed_ = subscribed;
}

void ConditioningRendererDiagnostics::report(diagnostic_updater::DiagnosticStatusWrapper& status) {
  std::lock_guard<std::mutex> lock(mutex_);
  const ros::WallTime now = ros::WallTime::now();
  const double seconds = std::max(1e-6, (now - window_start_).toSec());
  status.addf("synced sets rate (Hz)", "%.2f", window_.sets / seconds);
  status.addf("output rate (Hz)", "%.2f", window_.frames / seconds);
  const double frames = std::max<unsigned long>(1, window_.frames);
  status.addf("render mean (ms)", "%.1f", window_.render_sum_ms / frames);
  status.addf("render max (ms)", "%.1f", window_.render_max_ms);
  status.addf("frame mean (ms)", "%.1f", window_.frame_sum_ms / frames);
  const double all_frames = std::max<unsigned long>(1, total_.frames);
  status.addf("render mean since start (ms)", "%.1f", total_.render_sum_ms / all_frames);
  status.addf("frame mean since start (ms)", "%.1f", total_.frame_sum_ms / all_frames);
  status.add("synced sets total", total_.sets);
  status.add("published frames total", total_.frames);
  status.add("keyframes total", total_.keyframes);
  status.add("keyframe points", keyframe_points_);
  status.addf("keyframe cloud (ms)", "%.1f", keyframe_cloud_ms_);
  status.add("bursts total", total_.bursts);
  status.add("burst frames total", total_.burst_frames);
  if (total_.bursts > 0) {
    status.addf("burst mean (ms)", "%.1f", total_.burst_sum_ms / total_.bursts);
  }
  unsigned long rejected_total = 0, rejected_window = 0;
  for (int f = 1; f < rc::kRendererFaultCount; ++f) {
    rejected_total += total_.faults[f];
    rejected_window += window_.faults[f];
    status.add(std::string("rejected ") + rc::toString(static_cast<rc::RendererFault>(f)),
               total_.faults[f]);
  }
  status.add("rejected total", rejected_total);
  status.add("subscribed to inputs", subscribed_ ? "yes" : "no (no output subscriber, no export)");
  if (rejected_window > 0) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                    "%lu input sets dropped in the last %.1f s (see 'rejected ...')",
                    rejected_window, seconds);
  } else if (subscribed_ && window_.sets == 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "waiting for synchronized input");
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, subscribed_ ? "running" : "idle");
  }
  window_ = Counts();
  window_start_ = now;
}

}  // namespace multimodal_nvs
