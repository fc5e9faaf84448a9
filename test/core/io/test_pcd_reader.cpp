// PCD files through io::readPoints / io::parsePcd (PCL's reader behind checkPcdLayout): files
// written by PCL's own writer in all three encodings load with the same points, and malformed files
// (truncated, bad header, no x, corrupt binary_compressed) are InputErrors naming the file, before
// PCL allocates or reads what the header promises.
#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "core/input_error.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"

namespace io = multimodal_nvs::io;
using multimodal_nvs::test::inputErrorOf;

namespace {

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "mmnvs_pcd_" + name;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

/// Organised 4 x 3 cloud with values that print exactly in PCL's ascii (8 significant digits), one
/// missing return (NaN) as PCL marks it.
pcl::PointCloud<pcl::PointXYZI> organisedCloud() {
  pcl::PointCloud<pcl::PointXYZI> cloud(4, 3);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    cloud[i].x = 0.25f * i - 1.5f;
    cloud[i].y = -2.0f + 0.125f * i;
    cloud[i].z = 10.0f + i;
    cloud[i].intensity = 0.5f * i;
  }
  cloud[5].x = cloud[5].y = cloud[5].z = std::numeric_limits<float>::quiet_NaN();
  cloud.is_dense = false;
  return cloud;
}

/// 5,000 random points (LZF gets something to compress that is not a repeated pattern).
pcl::PointCloud<pcl::PointXYZI> randomCloud() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-80.0f, 80.0f);
  pcl::PointCloud<pcl::PointXYZI> cloud;
  for (int i = 0; i < 5000; ++i) {
    pcl::PointXYZI p;
    p.x = u(rng), p.y = u(rng), p.z = 0.1f * u(rng), p.intensity = static_cast<float>(i % 7);
    cloud.push_back(p);
  }
  return cloud;
}

std::vector<Eigen::Vector3f> finiteXyz(const pcl::PointCloud<pcl::PointXYZI>& cloud) {
  std::vector<Eigen::Vector3f> out;
  for (const auto& p : cloud) {
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      out.emplace_back(p.x, p.y, p.z);
  }
  return out;
}

enum class Encoding { kAscii, kBinary, kCompressed };

std::string savedByPcl(const pcl::PointCloud<pcl::PointXYZI>& cloud, Encoding encoding,
                       const std::string& name) {
  const std::string path = tempPath(name);
  int status = -1;
  if (encoding == Encoding::kAscii) status = pcl::io::savePCDFileASCII(path, cloud);
  if (encoding == Encoding::kBinary) status = pcl::io::savePCDFileBinary(path, cloud);
  if (encoding == Encoding::kCompressed) status = pcl::io::savePCDFileBinaryCompressed(path, cloud);
  EXPECT_EQ(status, 0) << path;
  return path;
}

/// The offset of the first payload byte (after "DATA ...\n").
std::size_t payloadOffset(const std::string& pcd) {
  return pcd.find('\n', pcd.find("\nDATA ") + 1) + 1;
}

}  // namespace

TEST(PcdReader, PclWrittenFilesOfEveryEncodingLoadTheirFinitePoints) {
  for (const auto& cloud : {organisedCloud(), randomCloud()}) {
    const auto expected = finiteXyz(cloud);
    for (Encoding e : {Encoding::kAscii, Encoding::kBinary, Encoding::kCompressed}) {
      if (e == Encoding::kAscii && cloud.size() > 100) continue;  // 8 digits do not round-trip
      const std::string path = savedByPcl(cloud, e, "pcl_" + std::to_string(int(e)) + ".pcd");
      const auto points = io::readPoints(path, io::PointFormat::kPcd);
      ASSERT_EQ(points.size(), expected.size()) << path;
      for (std::size_t i = 0; i < points.size(); ++i)
        ASSERT_EQ(points[i], expected[i]) << path << " point " << i;
    }
  }
  EXPECT_EQ(finiteXyz(organisedCloud()).size(), 11u);  // the NaN point is dropped
}

TEST(PcdReader, Float64CoordinatesFromPclsWriter) {
  // x, y, z as F8 after a multi-count U1 field, written by PCDWriter from a PCLPointCloud2.
  pcl::PCLPointCloud2 cloud;
  cloud.width = 2;
  cloud.height = 1;
  const auto field = [](const char* name, std::uint32_t offset, std::uint8_t type,
                        std::uint32_t count) {
    pcl::PCLPointField f;
    f.name = name, f.offset = offset, f.datatype = type, f.count = count;
    return f;
  };
  cloud.fields = {field("rgba", 0, pcl::PCLPointField::UINT8, 4),
                  field("x", 4, pcl::PCLPointField::FLOAT64, 1),
                  field("y", 12, pcl::PCLPointField::FLOAT64, 1),
                  field("z", 20, pcl::PCLPointField::FLOAT64, 1)};
  cloud.point_step = 28;
  cloud.row_step = 56;
  cloud.data.resize(56);
  const double xyz[2][3] = {{1.0 / 3.0, -2.5, 1e-3}, {100.125, 7.0, -0.0}};
  for (int i = 0; i < 2; ++i)
    std::memcpy(cloud.data.data() + 28 * i + 4, xyz[i], 24);
  pcl::PCDWriter writer;
  for (bool compressed : {false, true}) {
    const std::string path = tempPath(compressed ? "f8_c.pcd" : "f8_b.pcd");
    ASSERT_EQ(
        compressed ? writer.writeBinaryCompressed(path, cloud) : writer.writeBinary(path, cloud),
        0);
    const auto points = io::readPoints(path, io::PointFormat::kPcd);
    ASSERT_EQ(points.size(), 2u);
    for (int i = 0; i < 2; ++i) {
      EXPECT_EQ(points[i], Eigen::Vector3d(xyz[i][0], xyz[i][1], xyz[i][2]).cast<float>());
    }
  }
}

TEST(PcdReader, TruncatedBinaryNamesTheFileAndTheSizes) {
  const std::string full = readFile(savedByPcl(organisedCloud(), Encoding::kBinary, "t.pcd"));
  const std::string path = tempPath("truncated.pcd");
  writeFile(path, full.substr(0, full.size() - 4));
  const std::string error = inputErrorOf([&] { io::readPoints(path, io::PointFormat::kPcd); });
  EXPECT_EQ(error.rfind(path + ": PCD binary data is truncated", 0), 0u) << error;
  EXPECT_NE(error.find("12 points x 16 bytes need 192 bytes, the file has 188"), std::string::npos)
      << error;
}

TEST(PcdReader, HugePointCountsInATinyFileAreRejectedBeforeAnyAllocation) {
  // 4 billion points of 2 KB promised by 150 bytes: PCL would allocate that while reading the
  // header.
  const std::string header =
      "FIELDS x y z d\nSIZE 4 4 4 1\nTYPE F F F U\nCOUNT 1 1 1 2000\nWIDTH 4000000000\nHEIGHT 1\n"
      "POINTS 4000000000\nDATA ";
  for (const char* kind : {"binary\n", "binary_compressed\n", "ascii\n"}) {
    EXPECT_NE(inputErrorOf([&] {
                io::parsePcd(header + kind + "1 2 3\n", "huge.pcd");
              }).find("over 2 GiB"),
              std::string::npos)
        << kind;
  }
  // Within PCL's 2 GiB but still far more than the file holds.
  const std::string medium =
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 100000000\nHEIGHT 1\nPOINTS 100000000\nDATA ";
  EXPECT_NE(inputErrorOf([&] { io::parsePcd(medium + "binary\n", "m.pcd"); }).find("truncated"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([&] {
              io::parsePcd(medium + "ascii\n1 2 3\n", "m.pcd");
            }).find("ascii data is truncated: 1 of 100000000 rows"),
            std::string::npos);
}

TEST(PcdReader, BadHeadersSayWhichLineAndWhy) {
  const std::string fields = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n";
  const std::string shape = "WIDTH 1\nHEIGHT 1\nPOINTS 1\n";
  const std::string row = "DATA ascii\n1 2 3\n";
  const struct {
    std::string pcd, expected;
  } cases[] = {
      {fields + shape, "ends before a DATA line"},
      {fields + shape + "DATA ascii", "ends before a DATA line"},
      {"FIELDS x y z\nSIZE 4 4 3\nTYPE F F F\n" + shape + row, "line 2: SIZE of field z is 3"},
      {"FIELDS x y z\nSIZE 4 4 2\nTYPE F F F\n" + shape + row, "TYPE 'F' with SIZE 2"},
      {"FIELDS x y z\nSIZE 4 4\nTYPE F F F\n" + shape + row, "SIZE has 2 entries for 3 fields"},
      {fields + "COUNT 1 1 0\n" + shape + row, "COUNT of field z is 0"},
      {fields + "COUNT 1 1 2147483648\n" + shape + row, "bad COUNT '2147483648'"},
      {fields + "WIDTH -1\nHEIGHT 1\nPOINTS 1\n" + row, "bad WIDTH '-1'"},
      {fields + "WIDTH 99999999999999999999\nHEIGHT 1\nPOINTS 1\n" + row, "bad WIDTH"},
      {fields + "WIDTH 2\nHEIGHT 1\nPOINTS 1\n" + row, "WIDTH x HEIGHT (2 x 1) is not POINTS (1)"},
      {fields + "WIDTH 4294967295\nHEIGHT 4294967295\nPOINTS 1\n" + row, "is not POINTS"},
      {fields + "WIDTH 1\nHEIGHT 1\n" + row, "no POINTS before DATA"},
      {fields + "POINTS 1\n" + row, "no WIDTH or HEIGHT"},
      {"SIZE 4 4 4\nFIELDS x y z\nTYPE F F F\n" + shape + row, "line 1: no FIELDS"},
      {fields + "HEIGHT 1\nWIDTH 1\nPOINTS 1\n" + row, "line 5: WIDTH comes after HEIGHT"},
      {"FIELDS x y z\nTYPE F F F\n" + shape + row, "no SIZE"},
      {fields + shape + "POINTS 1\n" + row, "POINTS comes after POINTS"},
      {fields + "COLUMNS x y z\n" + shape + row, "'COLUMNS x y z' is not a PCD v0.7 header"},
      {fields + " \n" + shape + row, "is not a PCD v0.7 header entry"},
      {fields + "VIEWPOINT 0 0 0 1 0 0\n" + shape + row, "VIEWPOINT needs 7 numbers"},
      {fields + shape + "DATA binary_compresed\n", "DATA 'binary_compresed'"},
      // A NUL inside a number: PCL's stream extraction would stop there.
      {fields + std::string("WIDTH 1\0x\nHEIGHT 1\nPOINTS 1\n", 26) + row, "bad WIDTH"},
  };
  for (const auto& c : cases) {
    const std::string error = inputErrorOf([&] { io::parsePcd(c.pcd, "h.pcd"); });
    EXPECT_EQ(error.rfind("h.pcd: PCD ", 0), 0u) << c.pcd << "\n-> " << error;
    EXPECT_NE(error.find(c.expected), std::string::npos) << c.pcd << "\n-> " << error;
  }
  // Comments, empty lines, CRLF line ends and a VERSION are fine.
  const auto points = io::parsePcd(
      "# .PCD v0.7\r\n\nVERSION 0.7\r\n" + fields + shape + "DATA ascii\r\n1 2 3\r\n", "ok.pcd");
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0], Eigen::Vector3f(1, 2, 3));
}

TEST(PcdReader, CoordinatesMustBeFloatFields) {
  const std::string shape = "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n";
  EXPECT_NE(inputErrorOf([&] {
              io::parsePcd("FIELDS a y z\nSIZE 4 4 4\nTYPE F F F\n" + shape, "m.pcd");
            }).find("m.pcd: PCD has no field x"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([&] {
              io::parsePcd("FIELDS x y z\nSIZE 4 4 4\nTYPE U F F\n" + shape, "u.pcd");
            }).find("PCD field x is type 6 (4 bytes), expected F4 or F8"),
            std::string::npos);
}

TEST(PcdReader, AsciiRowsWithTheWrongNumberOfValuesAreErrorsNotZeroPoints) {
  // PCL's reader would count the short row as read and keep (0, 0, 0) for it.
  const std::string pcd =
      "FIELDS x y z i\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 3\nHEIGHT 1\nPOINTS 3\nDATA ascii\n"
      "1 2 3 4\n\n5 6 7\n8 9 10 11\n";
  EXPECT_NE(inputErrorOf([&] {
              io::parsePcd(pcd, "r.pcd");
            }).find("r.pcd: PCD ascii row 2 has 3 values, the header needs 4"),
            std::string::npos);
}

TEST(PcdReader, CorruptBinaryCompressedPayloadsAreErrorsAndPclStaysQuiet) {
  const std::string good = readFile(savedByPcl(randomCloud(), Encoding::kCompressed, "c.pcd"));
  const std::size_t payload = payloadOffset(good);
  const auto withWordsAt = [&](std::size_t at, std::uint32_t value) {
    std::string bad = good;
    std::memcpy(&bad[payload + at], &value, 4);
    return bad;
  };
  std::uint32_t compressed = 0;
  std::memcpy(&compressed, good.data() + payload, 4);
  ASSERT_EQ(good.size(), payload + 8 + compressed);
  // The first LZF token a back reference to before the output's start.
  std::string bad_reference = good;
  bad_reference.replace(payload + 8, 3, "\xff\xff\xff");
  const struct {
    std::string pcd, expected;
  } cases[] = {
      {bad_reference, "binary_compressed data is corrupt (LZF)"},
      {good.substr(0, good.size() - 1), "corrupt or truncated: " + std::to_string(compressed)},
      {good.substr(0, payload + 5), "truncated: no size words"},
      {withWordsAt(0, 0), "corrupt or truncated: 0 compressed bytes"},
      {withWordsAt(0, 0xffffffffu), "corrupt or truncated"},
      {withWordsAt(4, 12), "unpacks to 12 bytes, the header needs 80000"},
      {withWordsAt(4, 0xffffffffu), "unpacks to 4294967295 bytes"},
  };
  for (const auto& c : cases) {
    testing::internal::CaptureStderr();
    const std::string error = inputErrorOf([&] { io::parsePcd(c.pcd, "c.pcd"); });
    const std::string pcl_output = testing::internal::GetCapturedStderr();
    EXPECT_NE(error.find("c.pcd: PCD binary_compressed data "), std::string::npos) << error;
    EXPECT_NE(error.find(c.expected), std::string::npos) << error;
    EXPECT_EQ(pcl_output, "");
  }
  // More than LZF can expand to: 20 bytes cannot hold 80,000.
  std::string small = withWordsAt(0, 20);
  EXPECT_NE(inputErrorOf([&] { io::parsePcd(small, "c.pcd"); }).find("cannot unpack to 80000"),
            std::string::npos);
}
