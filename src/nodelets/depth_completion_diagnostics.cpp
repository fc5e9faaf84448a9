#include "depth_completion_diagnostics.hpp"

#include <algorithm>
#include <cmath>

namespace multimodal_nvs {

namespace rc = ros_conversions;

void DepthCompletionDiagnostics::start(ros::NodeHandle& nh, ros::NodeHandle& private_nh,
                                       const std::string& node_name) {
  counters_.start();
  publisher_.start(nh, private_nh, node_name, "depth completion",
                   [this](diagnostic_updater::DiagnosticStatusWrapper& status) { report(status); });
}

void DepthCompletionDiagnostics::countInput(FrameInput input) {
  counters_.update([input](Counts& counts) { ++counts.inputs[static_cast<int>(input)]; });
}

void DepthCompletionDiagnostics::countSet() {
  counters_.update([](Counts& counts) { ++counts.inputs[kSet]; });
}

void DepthCompletionDiagnostics::countFault(rc::InputFault fault) {
  counters_.update([fault](Counts& counts) { ++counts.faults[static_cast<int>(fault)]; });
}

void DepthCompletionDiagnostics::countPublished(double latency_ms, const DepthMapStats& stats) {
  counters_.update([&](Counts& counts) {
    ++counts.published;
    counts.latency_sum_ms += latency_ms;
    counts.latency_max_ms = std::max(counts.latency_max_ms, latency_ms);
    counts.compute_sum_ms += stats.compute_ms;
    counts.ground_source = stats.ground_source;
    counts.ground_camera_height = stats.ground_camera_height;
    counts.ground_pitch_deg = stats.ground_pitch_deg;
    counts.ground_roll_deg = stats.ground_roll_deg;
    counts.guided_return_density = stats.guided_return_density;
    counts.guided_prior_weight = stats.guided_prior_weight;
    counts.guided_band_top_deg = stats.guided_band_top_deg;
  });
}

void DepthCompletionDiagnostics::countTimeJump() {
  counters_.update([](Counts& counts) { ++counts.time_jumps; });
}

void DepthCompletionDiagnostics::countSubsampled(std::size_t step) {
  counters_.update([step](Counts& counts) {
    ++counts.subsampled;
    counts.max_subsample_step = std::max(counts.max_subsample_step, step);
  });
}

void DepthCompletionDiagnostics::setSubscribed(bool subscribed) {
  subscribed_ = subscribed;
}

void DepthCompletionDiagnostics::report(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const bool subscribed = subscribed_;
  counters_.closeWindow([&](const Counts& window, const Counts& total, double seconds) {
    static const char* const kInputNames[kSet + 1] = {"points", "image", "camera_info",
                                                      "synced sets"};
    for (int i = 0; i <= kSet; ++i) {
      status.addf(std::string(kInputNames[i]) + " rate (Hz)", "%.2f", window.inputs[i] / seconds);
    }
    status.addf("output rate (Hz)", "%.2f", window.published / seconds);
    const double published = std::max<unsigned long>(1, window.published);
    status.addf("latency mean (ms)", "%.1f", window.latency_sum_ms / published);
    status.addf("latency max (ms)", "%.1f", window.latency_max_ms);
    status.addf("compute mean (ms)", "%.1f", window.compute_sum_ms / published);
    status.add("synced sets total", total.inputs[kSet]);
    status.add("published total", total.published);
    const unsigned long rejected_window =
        addRejectedRows<rc::InputFault>(status, window.faults, total.faults);
    status.add("time jumps back", total.time_jumps);
    status.add("subsampled clouds", total.subsampled);
    status.add("largest subsampling step", total.max_subsample_step);
    status.add("subscribed to inputs", subscribed ? "yes" : "no (no output subscriber)");
    // The latest frame's plane (totals keep it across windows): a user checks it against the
    // vehicle, above all when it comes from the parameters.
    if (!total.ground_source.empty()) {
      status.add("ground plane source", total.ground_source);
      status.addf("ground plane camera height (m)", "%.2f", total.ground_camera_height);
      status.addf("ground plane pitch (deg)", "%.2f", total.ground_pitch_deg);
      status.addf("ground plane roll (deg)", "%.2f", total.ground_roll_deg);
    }
    // How dense the returns are and how much that moved image_guided's prior: another radar's
    // user sees whether the model treats it as sparse (VoD-like) or dense (Astyx-like).
    if (total.guided_prior_weight >= 0.0) {
      status.addf("returns per square degree", "%.3f", total.guided_return_density);
      status.addf("image_guided prior weight", "%.2e", total.guided_prior_weight);
      // Above this elevation no return measured the scene; the prior weighed more there.
      if (std::isfinite(total.guided_band_top_deg))
        status.addf("returns' band top (deg)", "%.2f", total.guided_band_top_deg);
      else
        status.add("returns' band top (deg)", "none (the prior weighs the same everywhere)");
    }
    if (rejected_window > 0) {
      status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                      "%lu input sets dropped in the last %.1f s (see 'rejected ...')",
                      rejected_window, seconds);
    } else if (window.time_jumps > 0) {
      status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                      "time went back %lu times in the last %.1f s (bag restarted?): started over",
                      window.time_jumps, seconds);
    } else if (subscribed && window.inputs[kSet] == 0) {
      status.summary(diagnostic_msgs::DiagnosticStatus::OK, "waiting for synchronized input");
    } else {
      status.summary(diagnostic_msgs::DiagnosticStatus::OK, subscribed ? "running" : "idle");
    }
  });
}

}  // namespace multimodal_nvs
