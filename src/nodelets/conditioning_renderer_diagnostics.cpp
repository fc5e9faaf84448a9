#include "conditioning_renderer_diagnostics.hpp"

#include <algorithm>

namespace multimodal_nvs {

namespace rc = ros_conversions;

void ConditioningRendererDiagnostics::start(ros::NodeHandle& nh, ros::NodeHandle& private_nh,
                                            const std::string& node_name) {
  counters_.start();
  publisher_.start(nh, private_nh, node_name, "conditioning renderer",
                   [this](diagnostic_updater::DiagnosticStatusWrapper& status) { report(status); });
}

void ConditioningRendererDiagnostics::countSet() {
  counters_.update([](Counts& counts) { ++counts.sets; });
}

void ConditioningRendererDiagnostics::countCameraImage() {
  counters_.update([](Counts& counts) { ++counts.camera_images; });
}

void ConditioningRendererDiagnostics::countCameraImageDropped() {
  counters_.update([](Counts& counts) { ++counts.camera_images_dropped; });
}

void ConditioningRendererDiagnostics::countLiveSkipped(int frames) {
  counters_.update(
      [&](Counts& counts) { counts.live_skipped += static_cast<unsigned long>(frames); });
}

void ConditioningRendererDiagnostics::countExport(ExportEnd end, int frames, double ms) {
  counters_.update([&](Counts& counts) {
    ++counts.exports[static_cast<std::size_t>(end)];
    if (end == ExportEnd::kComplete) {
      counts.burst_frames += static_cast<unsigned long>(frames);
      counts.export_sum_ms += ms;
    }
  });
}

void ConditioningRendererDiagnostics::countFault(rc::RendererFault fault) {
  counters_.update([fault](Counts& counts) { ++counts.faults[static_cast<int>(fault)]; });
}

void ConditioningRendererDiagnostics::countFrame(double render_ms, double frame_ms) {
  counters_.update([&](Counts& counts) {
    ++counts.frames;
    counts.render_sum_ms += render_ms;
    counts.render_max_ms = std::max(counts.render_max_ms, render_ms);
    counts.frame_sum_ms += frame_ms;
  });
}

void ConditioningRendererDiagnostics::countKeyframe(std::size_t points, double cloud_ms) {
  counters_.update([&](Counts& counts) {
    ++counts.keyframes;
    counts.keyframe_points = points;
    counts.keyframe_cloud_ms = cloud_ms;
  });
}

void ConditioningRendererDiagnostics::countBurst(int frames, double burst_ms) {
  counters_.update([&](Counts& counts) {
    ++counts.bursts;
    counts.burst_frames += static_cast<unsigned long>(frames);
    counts.burst_sum_ms += burst_ms;
  });
}

void ConditioningRendererDiagnostics::setSubscribed(bool subscribed) {
  subscribed_ = subscribed;
}

void ConditioningRendererDiagnostics::report(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const bool subscribed = subscribed_;
  counters_.closeWindow([&](const Counts& window, const Counts& total, double seconds) {
    status.addf("synced sets rate (Hz)", "%.2f", window.sets / seconds);
    status.addf("camera images rate (Hz)", "%.2f", window.camera_images / seconds);
    status.addf("output rate (Hz)", "%.2f", window.frames / seconds);
    const double frames = std::max<unsigned long>(1, window.frames);
    status.addf("render mean (ms)", "%.1f", window.render_sum_ms / frames);
    status.addf("render max (ms)", "%.1f", window.render_max_ms);
    status.addf("frame mean (ms)", "%.1f", window.frame_sum_ms / frames);
    const double all_frames = std::max<unsigned long>(1, total.frames);
    status.addf("render mean since start (ms)", "%.1f", total.render_sum_ms / all_frames);
    status.addf("frame mean since start (ms)", "%.1f", total.frame_sum_ms / all_frames);
    status.add("synced sets total", total.sets);
    status.add("camera images total", total.camera_images);
    status.add("published frames total", total.frames);
    status.add("camera images skipped (newer ones waiting)", total.live_skipped);
    status.add("camera images dropped (live-view queue full)", total.camera_images_dropped);
    status.add("keyframes total", total.keyframes);
    status.add("keyframe points", total.keyframe_points);
    status.addf("keyframe cloud (ms)", "%.1f", total.keyframe_cloud_ms);
    status.add("bursts total", total.bursts);
    status.add("burst frames total", total.burst_frames);
    if (total.bursts > 0) {
      status.addf("burst mean (ms)", "%.1f", total.burst_sum_ms / total.bursts);
    }
    using End = ExportEnd;
    const auto exports = [&](End end) { return total.exports[static_cast<std::size_t>(end)]; };
    status.add("exports complete", exports(End::kComplete));
    status.add("exports aborted (bag loop, missing tf, timeout)", exports(End::kAborted));
    status.add("exports cancelled", exports(End::kCancelled));
    status.add("exports failed (writing)", exports(End::kFailed));
    if (exports(End::kComplete) > 0) {
      status.addf("export mean (ms)", "%.1f", total.export_sum_ms / exports(End::kComplete));
    }
    const unsigned long rejected_window =
        addRejectedRows<rc::RendererFault>(status, window.faults, total.faults);
    status.add("subscribed to inputs", subscribed ? "yes" : "no (no output subscriber, no export)");
    if (rejected_window > 0) {
      status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                      "%lu input sets dropped in the last %.1f s (see 'rejected ...')",
                      rejected_window, seconds);
    } else if (subscribed && window.sets == 0) {
      status.summary(diagnostic_msgs::DiagnosticStatus::OK, "waiting for synchronized input");
    } else {
      status.summary(diagnostic_msgs::DiagnosticStatus::OK, subscribed ? "running" : "idle");
    }
  });
}

}  // namespace multimodal_nvs
