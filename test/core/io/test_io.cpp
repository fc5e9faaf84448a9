// File formats: npy round trip, KITTI calibration, point files (bin layouts; PCD files in
// test_pcd_reader.cpp), and every malformed input raising InputError with the file named.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "core/input_error.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"

namespace mm = multimodal_nvs;
namespace io = multimodal_nvs::io;

namespace {

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "mmnvs_io_" + name;
}

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

using multimodal_nvs::test::inputErrorOf;

const char* kCalib =
    "P2: 1495.5 0.0 961.3 0.0 0.0 1495.4 624.9 0.0 0.0 0.0 1.0 0.0\n"
    "Tr_velo_to_cam: 0 -1 0 0.1 0 0 -1 0.2 1 0 0 0.3\nTr_imu_to_velo:\n";

}  // namespace

TEST(Npy, RoundTripFloatAndUint8WithPaddedHeader) {
  const std::vector<float> values{1.5f, -1.0f, 3.25f, 0.0f, 7.0f, -2.5f};
  io::writeNpy(tempPath("f.npy"), values.data(), {2, 3});
  const auto a = io::readNpy(tempPath("f.npy"));
  EXPECT_EQ(a.dtype, "<f4");
  EXPECT_EQ(a.shape, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(a.asFloat(), values);
  const std::string header = io::npyHeader("<f4", {1, 121, 1, 3, 704, 1280});
  EXPECT_EQ(header.size() % 64, 0u);
  const std::vector<std::uint8_t> mask{0, 1, 1};
  io::writeNpy(tempPath("u.npy"), mask.data(), {3});
  EXPECT_EQ(io::readNpy(tempPath("u.npy")).asFloat(), (std::vector<float>{0, 1, 1}));
}

TEST(Npy, MalformedFilesAreRejected) {
  writeFile(tempPath("bad.npy"), "not numpy at all");
  EXPECT_NE(inputErrorOf([] { io::readNpy(tempPath("bad.npy")); }).find("bad magic"),
            std::string::npos);
  std::vector<float> v(6, 1.0f);
  io::writeNpy(tempPath("t.npy"), v.data(), {2, 3});
  std::ifstream in(tempPath("t.npy"), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  writeFile(tempPath("trunc.npy"), bytes.substr(0, bytes.size() - 5));
  EXPECT_NE(inputErrorOf([] { io::readNpy(tempPath("trunc.npy")); }).find("truncated"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] { io::readNpy(tempPath("missing.npy")); }).find("cannot open"),
            std::string::npos);
}

TEST(KittiCalib, ParsesIntrinsicsAndExtrinsic) {
  const auto calib = io::parseKittiCalib(kCalib, "calib.txt");
  const auto k = calib.intrinsics();
  EXPECT_DOUBLE_EQ(k.fx, 1495.5);
  EXPECT_DOUBLE_EQ(k.fy, 1495.4);
  EXPECT_DOUBLE_EQ(k.cx, 961.3);
  EXPECT_DOUBLE_EQ(k.cy, 624.9);
  const auto t = calib.sensorToCamera();
  EXPECT_DOUBLE_EQ(t(0, 1), -1.0);
  EXPECT_DOUBLE_EQ(t(2, 3), 0.3);
}

TEST(KittiCalib, ErrorsNameTheFileAndTheProblem) {
  const auto no_tr = io::parseKittiCalib("P2: 1 0 1 0 0 1 1 0 0 0 1 0\n", "a.txt");
  EXPECT_NE(inputErrorOf([&] { no_tr.sensorToCamera(); }).find("a.txt: no 'Tr_velo_to_cam:'"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] { io::parseKittiCalib("P2: 1 0 x 0\n", "b.txt"); }).find("unparsable"),
            std::string::npos);
  const auto zero_f = io::parseKittiCalib("P2: 0 0 1 0 0 1 1 0 0 0 1 0\n", "c.txt");
  EXPECT_NE(inputErrorOf([&] { zero_f.intrinsics(); }).find("focal length"), std::string::npos);
  const auto short_p = io::parseKittiCalib("P2: 1 0 1\n", "d.txt");
  EXPECT_NE(inputErrorOf([&] { short_p.intrinsics(); }).find("expected 12"), std::string::npos);
}

TEST(PointFiles, BinLayoutsAndSizeChecks) {
  std::vector<float> radar(14);
  for (int i = 0; i < 14; ++i)
    radar[i] = float(i);
  io::writeFloatRecords(tempPath("r.bin"), radar);
  const auto points = io::readPoints(tempPath("r.bin"), io::PointFormat::kVodRadar);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[1], Eigen::Vector3f(7, 8, 9));
  EXPECT_NE(inputErrorOf([] {
              io::readPoints(tempPath("r.bin"), io::PointFormat::kXyzi);
            }).find("not a multiple"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              io::readPoints(tempPath("nope.bin"), io::PointFormat::kXyz);
            }).find("cannot open"),
            std::string::npos);
}

TEST(VodLayout, FrameNumbersWithAndWithoutLeadingZeros) {
  EXPECT_EQ(io::parseFrameNumber("08350"), 8350);
  EXPECT_EQ(io::parseFrameNumber("8350"), 8350);
  EXPECT_THROW(io::parseFrameNumber("83a"), mm::InputError);
  EXPECT_EQ((io::VodFrame{"/r", 549}).points("radar"), "/r/radar/training/velodyne/00549.bin");
}
