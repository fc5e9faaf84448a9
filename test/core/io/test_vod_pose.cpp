// VoD pose files: one JSON object per line, camera-to-world 4x4 per key (View-of-Delft's dataset
// layout).
#include <gtest/gtest.h>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"
#include "test_data.hpp"

namespace mm = multimodal_nvs;

namespace {

const char* kTwoKeys =
    "{\"odomToCamera\": [1, 0, 0, 2.5, 0, 1, 0, -1, 0, 0, 1, 0.25, 0, 0, 0, 1]}\n"
    "{\"mapToCamera\": [0, -1, 0, 10, 1, 0, 0, 20, 0, 0, 1, 30, 0.0, 0.0, 0.0, 1.0]}\n";

std::string errorOf(const std::string& text, const std::string& key) {
  try {
    mm::io::parseVodPose(text, key, "pose.json");
  } catch (const mm::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(VodPose, SelectsKeyRowMajor) {
  const Eigen::Matrix4d map = mm::io::parseVodPose(kTwoKeys, "mapToCamera", "pose.json");
  EXPECT_EQ(map(0, 1), -1.0);
  EXPECT_EQ(map(1, 0), 1.0);
  EXPECT_EQ(map(0, 3), 10.0);
  EXPECT_EQ(map(2, 3), 30.0);
  const Eigen::Matrix4d odom = mm::io::parseVodPose(kTwoKeys, "odomToCamera", "pose.json");
  EXPECT_EQ(odom(0, 3), 2.5);
  EXPECT_EQ(odom(1, 3), -1.0);
  EXPECT_EQ(std::string(mm::io::defaultVodPoseKey()), "mapToCamera");
  EXPECT_EQ(mm::io::vodPoseKeys(kTwoKeys, "pose.json"),
            (std::vector<std::string>{"odomToCamera", "mapToCamera"}));
}

TEST(VodPose, MissingKeyListsKeysPresent) {
  const std::string e = errorOf(kTwoKeys, "UTMToCamera");
  EXPECT_NE(e.find("pose.json"), std::string::npos);
  EXPECT_NE(e.find("UTMToCamera"), std::string::npos);
  EXPECT_NE(e.find("odomToCamera, mapToCamera"), std::string::npos);
}

TEST(VodPose, MalformedJsonNamesLine) {
  const std::string e = errorOf(
      "{\"mapToCamera\": [1, 0, 0, 0,\n 0, 1, 0, 0 0, 0, 1, 0, 0, 0, 0, 1]}", "mapToCamera");
  EXPECT_NE(e.find("pose.json:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("malformed"), std::string::npos) << e;
  EXPECT_NE(errorOf("", "mapToCamera").find("empty"), std::string::npos);
  EXPECT_NE(errorOf("{\"mapToCamera\": [1, 2", "mapToCamera").find("malformed"), std::string::npos);
  EXPECT_NE(errorOf("{mapToCamera: []}", "mapToCamera").find("malformed"), std::string::npos);
}

TEST(VodPose, RejectsWrongShapeAndNonRigid) {
  EXPECT_NE(errorOf("{\"mapToCamera\": [1, 0, 0]}", "mapToCamera").find("16 numbers"),
            std::string::npos);
  EXPECT_NE(errorOf("{\"mapToCamera\": \"identity\"}", "mapToCamera").find("16 numbers"),
            std::string::npos);
  // Scaled rotation.
  EXPECT_NE(
      errorOf("{\"mapToCamera\": [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1]}", "mapToCamera")
          .find("orthonormal"),
      std::string::npos);
  // Reflection.
  EXPECT_NE(
      errorOf("{\"mapToCamera\": [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}", "mapToCamera")
          .find("determinant"),
      std::string::npos);
  EXPECT_NE(
      errorOf("{\"mapToCamera\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1]}", "mapToCamera")
          .find("last row"),
      std::string::npos);
  // NaN is not JSON; a number too large for a double is not accepted either.
  EXPECT_NE(errorOf("{\"mapToCamera\": [1, 0, 0, NaN, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}",
                    "mapToCamera")
                .find("malformed"),
            std::string::npos);
  EXPECT_NE(errorOf("{\"mapToCamera\": [1, 0, 0, 1e999, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}",
                    "mapToCamera")
                .find("malformed"),
            std::string::npos);
  EXPECT_THROW(mm::io::readVodPose("/nonexistent/pose.json"), mm::InputError);
}

TEST(VodPose, RealFileIsCameraToWorldWithCameraAboveGround) {
  const mm::io::VodFrame frame{mm::test::dataDir() + "/vod", 8350};
  MMNVS_REQUIRE_DATA(frame.pose());
  for (const char* key : {"odomToCamera", "mapToCamera", "UTMToCamera"}) {
    const Eigen::Matrix4d c2w = mm::io::readVodPose(frame.pose(), key);
    // View-of-Delft's pose convention: the camera sits ~1.3 m above the ground (z of the world
    // frame is up) and its optical y axis (down) points along -z of the world.
    EXPECT_NEAR(c2w(2, 3), 1.3, 0.1) << key;
    EXPECT_LT(c2w(2, 1), -0.9) << key;
  }
}
