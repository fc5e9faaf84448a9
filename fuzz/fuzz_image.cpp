// sensor_msgs/Image -> the pixels the node reads (ros_conversions::validateImage, colourFromImage
// in RGB and BGR order, frameImage): encoding, size, step and data all come from the input (layout
// in fuzz_input.hpp). Besides memory errors and UB, checks that every entry point refuses the same
// messages for the same reason, and that an accepted one gives the image's size in both orders,
// their channels swapped. (Compressed images are decoded by OpenCV's own decoders, fuzzed
// upstream.)
#include <opencv2/core.hpp>

#include "fuzz_input.hpp"
#include "multimodal_nvs/ros/conversions.hpp"

namespace rc = multimodal_nvs::ros_conversions;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const sensor_msgs::Image image = mmnvs_fuzz::imageFromBytes(data, size);
  const rc::ConversionStatus valid = rc::validateImage(image);
  cv::Mat rgb, bgr;
  const rc::ConversionStatus as_rgb = rc::colourFromImage(image, rc::ChannelOrder::kRgb, rgb);
  const rc::ConversionStatus as_bgr = rc::colourFromImage(image, rc::ChannelOrder::kBgr, bgr);
  rc::FrameImage frame;
  const rc::ConversionStatus framed = rc::frameImage(image, frame);
  MMNVS_FUZZ_CHECK(as_rgb.fault == valid.fault && as_bgr.fault == valid.fault);
  MMNVS_FUZZ_CHECK(framed.fault == valid.fault);
  if (!valid.ok()) {
    MMNVS_FUZZ_CHECK(!valid.reason.empty());
    return 0;
  }
  for (const cv::Mat* out : {&rgb, &bgr}) {
    MMNVS_FUZZ_CHECK(out->type() == CV_8UC3);
    MMNVS_FUZZ_CHECK(out->rows == int(image.height) && out->cols == int(image.width));
  }
  MMNVS_FUZZ_CHECK(frame.size.height == int(image.height) && frame.size.width == int(image.width));
  // The two orders hold the same pixels, R and B exchanged (first and last pixel).
  for (const cv::Point at : {cv::Point(0, 0), cv::Point(rgb.cols - 1, rgb.rows - 1)}) {
    const cv::Vec3b a = rgb.at<cv::Vec3b>(at), b = bgr.at<cv::Vec3b>(at);
    MMNVS_FUZZ_CHECK(a[0] == b[2] && a[1] == b[1] && a[2] == b[0]);
  }
  cv::Mat from_frame;
  MMNVS_FUZZ_CHECK(frame.bgr(from_frame).ok() && from_frame.size() == bgr.size());
  return 0;
}
