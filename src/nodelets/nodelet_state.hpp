#pragma once
// State kept alike by both nodelets: their dynamic_reconfigure settings, the engine a frame runs
// on, and the throttle of their "dropping input set" errors.
#include <ros/time.h>

#include <array>
#include <cstddef>
#include <mutex>
#include <optional>
#include <string>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/thread_count_cached.hpp"

namespace multimodal_nvs {

/// Settings written by the reconfigure callback and copied once per frame by the frame callback.
template <class Settings>
class GuardedSettings {
 public:
  void set(const Settings& settings) {
    std::lock_guard<std::mutex> lock(mutex_);
    settings_ = settings;
  }

  Settings get() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return settings_;
  }

  /// Applies `from_config(config)`. When that throws InputError the settings in effect stay and are
  /// written back into `config` by `to_config(settings, config)`, so that the reconfigure server
  /// publishes what is in effect; the error's message is returned then.
  template <class Config, class FromConfig, class ToConfig>
  std::optional<std::string> reconfigure(Config& config, FromConfig&& from_config,
                                         ToConfig&& to_config) {
    std::lock_guard<std::mutex> lock(mutex_);
    try {
      settings_ = from_config(config);
    } catch (const InputError& e) {
      to_config(settings_, config);
      return std::string(e.what());
    }
    return std::nullopt;
  }

 private:
  mutable std::mutex mutex_;
  Settings settings_;
};

/// Throttles the log of rejected inputs per reason, so that one recurring fault does not hide
/// another. Not thread-safe: used by one frame callback at a time.
template <std::size_t kFaultCount>
class PerFaultLogThrottle {
 public:
  /// True when `fault` was not logged in the last two seconds; it then counts as logged now.
  template <class Fault>
  bool due(Fault fault) {
    const ros::WallTime now = ros::WallTime::now();
    ros::WallTime& last = last_logged_[static_cast<std::size_t>(fault)];
    if (!last.isZero() && (now - last).toSec() < 2.0) return false;
    last = now;
    return true;
  }

 private:
  std::array<ros::WallTime, kFaultCount> last_logged_{};
};

}  // namespace multimodal_nvs
