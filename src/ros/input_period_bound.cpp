#include "multimodal_nvs/ros/input_period_bound.hpp"

#include <cmath>

namespace multimodal_nvs {

bool InputPeriodBound::observe(double stamp) {
  if (!std::isfinite(stamp)) return false;
  const bool had_last = has_last_;
  const double interval = stamp - last_;
  has_last_ = true;
  last_ = stamp;
  if (!had_last || !(interval > 0.0) || !(fraction_ > 0.0)) return false;
  if (intervals_ == 0 || interval < shortest_) shortest_ = interval;
  if (intervals_ < min_intervals_) ++intervals_;
  if (intervals_ < min_intervals_) return false;
  const double bound = fraction_ * shortest_;
  if (bound == bound_) return false;
  bound_ = bound;
  return true;
}

}  // namespace multimodal_nvs
