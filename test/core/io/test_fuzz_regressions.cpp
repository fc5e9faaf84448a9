// Inputs that crashed or misled the core readers, found with the libFuzzer harnesses of fuzz/
// (`make fuzz`), kept as regression tests. Each input is built in code; the comment says what it
// broke. Undefined behaviour (as opposed to a crash or a wrong result) shows only in the sanitizer
// build of these tests.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/input_error.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"

namespace mm = multimodal_nvs;
namespace io = multimodal_nvs::io;

namespace {

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "mmnvs_fuzz_regression_" + name;
}

using multimodal_nvs::test::inputErrorOf;

const char* kIdentity = "[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]";

/// A PCD header with fields x y z a, COUNT of `a` as given, and one ascii row.
std::string pcdWithCount(const std::string& count_of_a, const std::string& width = "1") {
  return "FIELDS x y z a\nSIZE 4 4 4 1\nTYPE F F F U\nCOUNT 1 1 1 " + count_of_a + "\nWIDTH " +
         width + "\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3 4\n";
}

std::string npyWithShape(const std::string& shape) {
  const std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': " + shape + ", }\n";
  return std::string("\x93NUMPY\x01\x00", 8) + static_cast<char>(dict.size()) + '\0' + dict;
}

}  // namespace

// fuzz_bin, empty input: the all-fields reader passed the null data() of an empty vector to memcpy
// (UB even for 0 bytes). An empty scan is a valid scan with no points.
TEST(FuzzRegression, EmptyBinFileHasNoRecords) {
  EXPECT_TRUE(io::parseFloatRecordValues("", 7, "empty.bin").empty());
  EXPECT_TRUE(io::parseFloatRecords("", 4, "empty.bin").empty());
  const std::string path = tempPath("empty.bin");
  std::ofstream(path, std::ios::binary).close();
  EXPECT_TRUE(io::readFloatRecords(path, 4).empty());
  EXPECT_TRUE(io::readPoints(path, io::PointFormat::kVodRadar).empty());
}

// fuzz_vod_pose, deeply nested arrays (found replaying a 100 kB input through the harness; the 4 kB
// runs stop short of the stack): the hand-written reader recursed once per '[' or '{' and
// overflowed the stack. nlohmann-json parses and destroys iteratively; these inputs stay clean
// errors.
TEST(FuzzRegression, DeeplyNestedPoseJsonIsRejectedNotAStackOverflow) {
  const std::string arrays = "{\"x\": " + std::string(100000, '[');
  EXPECT_NE(inputErrorOf([&] { io::vodPoseKeys(arrays, "deep.json"); }).find("deep.json:1:"),
            std::string::npos);
  std::string objects;
  for (int i = 0; i < 50000; ++i)
    objects += "{\"a\": ";
  EXPECT_NE(inputErrorOf([&] {
              io::parseVodPose(objects, "mapToCamera", "deep.json");
            }).find("malformed pose JSON"),
            std::string::npos);
  // Deeply nested but well-formed metadata is read.
  const std::string metadata = std::string("{\"mapToCamera\": ") + kIdentity +
                               ", \"meta\": " + std::string(100000, '[') +
                               std::string(100000, ']') + "}";
  EXPECT_EQ(io::parseVodPose(metadata, "mapToCamera", "ok.json"), Eigen::Matrix4d::Identity());
}

// fuzz_pcd: COUNT near INT_MAX after x, y, z made the running column sum overflow int (signed
// overflow, UB); values that do not fit in int were silently truncated ("4294967297" read as 1) and
// "-1" was read as 2^64 - 1. (PCL's reader, now behind checkPcdLayout, keeps point sizes in int.)
TEST(FuzzRegression, PcdCountsOutOfRangeAreRejected) {
  EXPECT_NE(inputErrorOf([] {
              io::parsePcd(pcdWithCount("2147483647"), "c.pcd");
            }).find("PCD point is too large"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              io::parsePcd(pcdWithCount("2147483648"), "c.pcd");
            }).find("bad COUNT '2147483648'"),
            std::string::npos);
  EXPECT_NE(
      inputErrorOf([] { io::parsePcd(pcdWithCount("4294967297"), "c.pcd"); }).find("bad COUNT"),
      std::string::npos);
  EXPECT_NE(inputErrorOf([] { io::parsePcd(pcdWithCount("1", "-1"), "c.pcd"); }).find("bad WIDTH"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              io::parsePcd(pcdWithCount("1", "99999999999999999999"), "c.pcd");
            }).find("bad WIDTH"),
            std::string::npos);
  const auto points = io::parsePcd(pcdWithCount("1"), "c.pcd");
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0], Eigen::Vector3f(1, 2, 3));
}

// fuzz_pcd: WIDTH * HEIGHT wrapped around (2^32 * 2^32 = 0 points, an "empty" cloud). PCL's reader
// compares WIDTH * HEIGHT with POINTS in 32 bits, so the product is checked in 64 bits first.
TEST(FuzzRegression, PcdWidthTimesHeightOverflowIsRejected) {
  const std::string pcd =
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 65536\nHEIGHT 65536\nPOINTS 0\n"
      "DATA binary\n";
  EXPECT_NE(inputErrorOf([&] {
              io::parsePcd(pcd, "o.pcd");
            }).find("WIDTH x HEIGHT (65536 x 65536) is not POINTS (0)"),
            std::string::npos);
}

// fuzz_npy: a negative dimension was read as 2^64 - 1; with another dimension 0 the array passed
// as an empty array of shape (18446744073709551615, 0).
TEST(FuzzRegression, NpyNegativeOrOverflowingDimensionsAreRejected) {
  EXPECT_NE(
      inputErrorOf([] { io::parseNpy(npyWithShape("(-1, 0)"), "n.npy"); }).find("bad .npy shape"),
      std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              io::parseNpy(npyWithShape("(0, 99999999999999999999)"), "n.npy");
            }).find("bad .npy shape"),
            std::string::npos);
  const io::NpyArray empty = io::parseNpy(npyWithShape("(0, 3)"), "n.npy");
  EXPECT_EQ(empty.shape, (std::vector<std::size_t>{0, 3}));
  EXPECT_EQ(empty.elementCount(), 0u);
}
