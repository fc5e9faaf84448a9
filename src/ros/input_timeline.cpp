#include "multimodal_nvs/ros/input_timeline.hpp"

#include <string>

namespace multimodal_nvs {

namespace rc = ros_conversions;

bool InputTimeline::clockJumpedBack(const ros::Time& now, ros::Duration* jump) {
  if (!clock_.jumpedBack(now, jump)) return false;
  stamps_.reset();
  return true;
}

InputTimeline::Admission InputTimeline::admit(const ros::Time& stamp) {
  const ros::Time last = stamps_.last();
  Admission admission;
  switch (stamps_.check(stamp)) {
    case StampOrder::Verdict::kNewer:
      break;
    case StampOrder::Verdict::kRestart:
      admission.restarted = true;
      admission.back = last - stamp;
      break;
    case StampOrder::Verdict::kNotNewer:
      admission.status = rc::ConversionStatus::failure(
          rc::InputFault::kStampNotNewer, "image stamp " + std::to_string(stamp.toSec()) +
                                              (stamp == last ? " repeats" : " precedes") +
                                              " the last processed set's " +
                                              std::to_string(last.toSec()));
      break;
  }
  return admission;
}

}  // namespace multimodal_nvs
