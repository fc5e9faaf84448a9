#include "multimodal_nvs/ros/frame_synchronizer.hpp"

#include <cmath>

namespace multimodal_nvs {

std::string syncSettingsProblem(const SyncSettings& settings) {
  std::string problem;
  const auto add = [&problem](const std::string& sentence) {
    problem += (problem.empty() ? "" : " ") + sentence;
  };
  if (settings.queue_size < 1) add("queue_size must be at least 1.");
  if (!std::isfinite(settings.max_interval) || settings.max_interval < 0.0)
    add("max_interval must be a finite number >= 0 (0: no limit).");
  // message_filters asserts on a negative age penalty: it would abort the process.
  if (!std::isfinite(settings.age_penalty) || settings.age_penalty < 0.0)
    add("sync_age_penalty must be a finite number >= 0.");
  if (!std::isfinite(settings.period_bound_fraction) || settings.period_bound_fraction < 0.0 ||
      settings.period_bound_fraction >= 1.0)
    add("sync_period_bound_fraction must be in [0, 1) (0: no bound).");
  return problem;
}

}  // namespace multimodal_nvs
