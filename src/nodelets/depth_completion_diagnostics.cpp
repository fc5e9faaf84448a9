#include "depth_completion_diagnostics.hpp"

namespace multimodal_nvs {

namespace rc = ros_conversions;

void DepthCompletionDiagnostics::start(ros::NodeHandle& nh, ros::NodeHandle& private_nh,
                                       const std::string& node_name) {
  window_start_ = ros::WallTime::now();
  publisher_.start(nh, private_nh, node_name, "depth completion",
                   [this](diagnostic_updater::DiagnosticStatusWrapper& status) { report(status); });
}

void DepthCompletionDiagnostics::countInput(Input input) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++window_.inputs[static_cast<int>(input)];
  ++total_.inputs[static_cast<int>(input)];
}

void DepthCompletionDiagnostics::countFault(rc::InputFault fault) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++window_.faults[static_cast<int>(fault)];
  ++total_.faults[static_cast<int>(fault)];
}

void DepthCompletionDiagnostics::countPublished(double latency_ms, double compute_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (Counts* counts : {&window_, &total_}) {
    ++counts->published;
    counts->latency_sum_ms += latency_ms;
    counts->latency_max_ms = std::max(counts->latency_max_ms, latency_ms);
    counts->compute_sum_ms += compute_ms;
  }
}

void DepthCompletionDiagnostics::countTimeJump() {
  std::lock_guard<std::mutex> lock(mutex_);
  ++window_.time_jumps;
  ++total_.time_jumps;
}

void DepthCompletionDiagnostics::countSubsampled(std::size_t step) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (Counts* counts : {&window_, &total_}) {
    ++counts->subsampled;
    counts->max_subsample_step = std::max(counts->max_subsample_step, step);
  }
}

void DepthCompletionDiagnostics::setSubscribed(bool subscribed) {
  std::lock_guard<std::mutex> lock(mutex_);
  subscribed_ = subscribed;
}

void DepthCompletionDiagnostics::report(diagnostic_updater::DiagnosticStatusWrapper& status) {
  std::lock_guard<std::mutex> lock(mutex_);
  const ros::WallTime now = ros::WallTime::now();
  const double seconds = std::max(1e-6, (now - window_start_).toSec());
  static const char* const kInputNames[4] = {"points", "image", "camera_info", "synced sets"};
  for (int i = 0; i < 4; ++i) {
    status.addf(std::string(kInputNames[i]) + " rate (Hz)", "%.2f", window_.inputs[i] / seconds);
  }
  status.addf("output rate (Hz)", "%.2f", window_.published / seconds);
  const double published = std::max<unsigned long>(1, window_.published);
  status.addf("latency mean (ms)", "%.1f", window_.latency_sum_ms / published);
  status.addf("latency max (ms)", "%.1f", window_.latency_max_ms);
  status.addf("compute mean (ms)", "%.1f", window_.compute_sum_ms / published);
  status.add("synced sets total", total_.inputs[static_cast<int>(Input::kSet)]);
  status.add("published total", total_.published);
  unsigned long rejected_total = 0, rejected_window = 0;
  for (int f = 1; f < rc::kInputFaultCount; ++f) {
    rejected_total += total_.faults[f];
    rejected_window += window_.faults[f];
    status.add(std::string("rejected ") + rc::toString(static_cast<rc::InputFault>(f)),
               total_.faults[f]);
  }
  status.add("rejected total", rejected_total);
  status.add("time jumps back", total_.time_jumps);
  status.add("subsampled clouds", total_.subsampled);
  status.add("largest subsampling step", total_.max_subsample_step);
  status.add("subscribed to inputs", subscribed_ ? "yes" : "no (no output subscriber)");
  if (rejected_window > 0) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                    "%lu input sets dropped in the last %.1f s (see 'rejected ...')",
                    rejected_window, seconds);
  } else if (window_.time_jumps > 0) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                    "time went back %lu times in the last %.1f s (bag restarted?): started over",
                    window_.time_jumps, seconds);
  } else if (subscribed_ && window_.inputs[static_cast<int>(Input::kSet)] == 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "waiting for synchronized input");
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, subscribed_ ? "running" : "idle");
  }
  window_ = Counts();
  window_start_ = now;
}

}  // namespace multimodal_nvs
