// Writes the seed corpora of the harnesses: `write_fuzz_seeds DIR` creates DIR/<harness>/ with
// valid inputs of each kind, made with the package's own writers where it has them, so that the
// fuzzers start from files the readers accept instead of discovering every header from scratch.
#include <pcl/io/pcd_io.h>
#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <vector>

#include "fuzz_input.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"

namespace io = multimodal_nvs::io;

namespace {

std::string makeDir(const std::string& dir) {
  if (::mkdir(dir.c_str(), 0755) != 0 && errno != EEXIST) {
    throw std::runtime_error("cannot create " + dir);
  }
  return dir;
}

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

template <typename T>
void append(std::vector<std::uint8_t>& data, T value) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
  data.insert(data.end(), p, p + sizeof value);
}

sensor_msgs::PointField field(const std::string& name, std::uint32_t offset,
                              std::uint8_t datatype) {
  sensor_msgs::PointField f;
  f.name = name;
  f.offset = offset;
  f.datatype = datatype;
  f.count = 1;
  return f;
}

void cloudSeeds(const std::string& dir) {
  using PF = sensor_msgs::PointField;
  // Unorganised xyz float32, dense.
  sensor_msgs::PointCloud2 xyz;
  xyz.height = 1;
  xyz.width = 4;
  xyz.point_step = 12;
  xyz.row_step = 48;
  xyz.is_dense = 1;
  xyz.fields = {field("x", 0, PF::FLOAT32), field("y", 4, PF::FLOAT32), field("z", 8, PF::FLOAT32)};
  for (int i = 0; i < 12; ++i)
    append<float>(xyz.data, 0.5f * i - 2.0f);
  writeFile(dir + "/xyz_float32", mmnvs_fuzz::bytesFromCloud(xyz));

  // VoD radar layout: 7 float32 fields, x/y/z first, two points.
  sensor_msgs::PointCloud2 radar;
  radar.height = 1;
  radar.width = 2;
  radar.point_step = 28;
  radar.row_step = 56;
  const char* names[7] = {"x", "y", "z", "rcs", "vr", "vrc", "t"};
  for (int i = 0; i < 7; ++i)
    radar.fields.push_back(field(names[i], 4 * i, PF::FLOAT32));
  for (int i = 0; i < 14; ++i)
    append<float>(radar.data, 1.0f + i);
  writeFile(dir + "/radar_vod7", mmnvs_fuzz::bytesFromCloud(radar));

  // Organised 3x2 float64 cloud with padding between rows, z before x, and NaN returns.
  sensor_msgs::PointCloud2 organised;
  organised.height = 2;
  organised.width = 3;
  organised.point_step = 32;
  organised.row_step = 3 * 32 + 8;
  organised.fields = {field("z", 0, PF::FLOAT64), field("x", 8, PF::FLOAT64),
                      field("y", 16, PF::FLOAT64), field("i", 24, PF::UINT16)};
  for (int row = 0; row < 2; ++row) {
    for (int col = 0; col < 3; ++col) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      append<double>(organised.data, col == 1 ? nan : 5.0 + row);
      append<double>(organised.data, col - 1.0);
      append<double>(organised.data, row * 0.25);
      append<std::uint64_t>(organised.data, 100 + col);
    }
    append<std::uint64_t>(organised.data, 0);  // row padding
  }
  writeFile(dir + "/organised_float64_nan", mmnvs_fuzz::bytesFromCloud(organised));
}

void kittiSeeds(const std::string& dir) {
  multimodal_nvs::PinholeIntrinsics k{1495.5, 1495.5, 961.3, 624.9};
  multimodal_nvs::SensorToCamera m = multimodal_nvs::SensorToCamera::Zero();
  m(0, 1) = -1.0;
  m(1, 2) = -1.0;
  m(2, 0) = 1.0;
  m(2, 3) = -0.27;
  io::writeKittiCalib(dir + "/written", k, m);
  // VoD's own layout: CRLF line ends, scientific notation, a key without numbers.
  writeFile(dir + "/vod_style",
            "P0: 1.495e+03 0 9.61e+02 0 0 1.495e+03 6.249e+02 0 0 0 1 0\r\n"
            "P2: 1495.468642 0.0 961.272442 0.0 0.0 1495.468642 624.89592 0.0 0.0 0.0 1.0 0.0\r\n"
            "R0_rect: 1 0 0 0 1 0 0 0 1\r\n"
            "Tr_velo_to_cam: -0.013857 -0.9997468 0.01772762 0.05283124 0.10934269 -0.01913807 "
            "-0.99381983 0.98100483 0.99390751 -0.01183297 0.1095802 1.44445002\r\n"
            "Tr_imu_to_velo:\r\n");
}

void cameraInfoSeeds(const std::string& dir) {
  // As the ROS camera calibrator writes it (../shared/data/distorted_camera), and a flow-style
  // rational_polynomial variant without the optional keys.
  writeFile(dir + "/plumb_bob",
            "image_width: 1920\nimage_height: 1200\ncamera_name: center_camera\n"
            "camera_matrix:\n  rows: 3\n  cols: 3\n"
            "  data: [2109.75, 0.0, 949.828, 0.0, 2071.72, 576.237, 0.0, 0.0, 1.0]\n"
            "distortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n"
            "  data: [-0.108145, 0.138668, -0.0037976, -0.0048413, 0.0]\n"
            "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n"
            "projection_matrix:\n  rows: 3\n  cols: 4\n"
            "  data: [2109.75, 0, 949.828, 0, 0, 2071.72, 576.237, 0, 0, 0, 1, 0]\n");
  writeFile(dir + "/rational_flow",
            "{image_width: 640, image_height: 480, camera_matrix: {data: [400, 0, 320, 0, 410, "
            "240, 0, 0, 1]}, distortion_model: rational_polynomial, distortion_coefficients: "
            "{rows: 1, cols: 8, data: [0.8, 0.15, 0.001, -0.002, 0.003, 1.1, 0.35, 0.02]}}\n");
}

void poseSeeds(const std::string& dir) {
  const std::string rotation =
      "[0.0, -1.0, 0.0, 1.5, 0.0, 0.0, -1.0, 0.25, 1.0, 0.0, 0.0, -3e2, "
      "0.0, 0.0, 0.0, 1.0]";
  writeFile(dir + "/vod_line",
            "{\"odomToCamera\": " + rotation + ", \"mapToCamera\": " + rotation +
                ", \"UTMToCamera\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], "
                "\"timestamp\": 1.5e9, \"name\": \"frame \\\"00001\\\"\", \"ok\": true, "
                "\"extra\": {\"nested\": [null, false, {}], \"empty\": []}}\n");
  writeFile(dir + "/json_lines",
            "{\"mapToCamera\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}\n"
            "{\"mapToCamera\": [1.0, 0.0, 0.0, -2.5, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 4.0, 0, 0, "
            "0, 1]}\n");
}

void binSeeds(const std::string& dir) {
  std::vector<float> radar;
  for (int i = 0; i < 3 * 7; ++i)
    radar.push_back(0.1f * i - 1.0f);
  io::writeFloatRecords(dir + "/radar_3x7", radar);
  std::vector<float> lidar;
  for (int i = 0; i < 5 * 4; ++i)
    lidar.push_back(i % 4 == 3 ? 0.5f : 2.0f * i);
  lidar[5] = std::numeric_limits<float>::quiet_NaN();
  io::writeFloatRecords(dir + "/lidar_5x4", lidar);
}

void pcdSeeds(const std::string& dir) {
  const std::string header =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
      "FIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
      "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\n";
  writeFile(dir + "/ascii_xyzi",
            header + "DATA ascii\n1.0 2.0 3.0 0.5\n-1 -2.5e1 nan 7\n0.001 1e3 -0 1\n");
  std::string binary = header + "DATA binary\n";
  for (int i = 0; i < 12; ++i) {
    const float v = 0.75f * i;
    binary.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  writeFile(dir + "/binary_xyzi", binary);
  // float64 x, y, z after a multi-count field, organised.
  std::string f8 =
      "VERSION 0.7\nFIELDS rgb x y z\nSIZE 1 8 8 8\nTYPE U F F F\nCOUNT 4 1 1 1\n"
      "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary\n";
  for (int i = 0; i < 2; ++i) {
    f8.append("\x10\x20\x30\x40", 4);
    for (int a = 0; a < 3; ++a) {
      const double v = i + 0.1 * a;
      f8.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
  }
  writeFile(dir + "/binary_rgb_f8", f8);
  // binary_compressed as PCL writes it (fields one after another, LZF): an organised 4 x 2 cloud
  // with a missing return, and 40 points whose repeats give LZF back references.
  for (const std::uint32_t width : {4u, 40u}) {
    pcl::PCLPointCloud2 cloud;
    cloud.width = width;
    cloud.height = width == 4 ? 2 : 1;
    const char* names[] = {"x", "y", "z", "intensity"};
    for (std::uint32_t f = 0; f < 4; ++f) {
      pcl::PCLPointField field;
      field.name = names[f], field.offset = 4 * f, field.count = 1;
      field.datatype = pcl::PCLPointField::FLOAT32;
      cloud.fields.push_back(field);
    }
    cloud.point_step = 16;
    cloud.row_step = 16 * cloud.width;
    for (std::uint32_t i = 0; i < 4 * cloud.width * cloud.height; ++i) {
      const float v = i == 5 ? std::numeric_limits<float>::quiet_NaN() : 0.5f * (i % 12);
      const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
      cloud.data.insert(cloud.data.end(), p, p + 4);
    }
    std::ostringstream out;
    if (pcl::PCDWriter().writeBinaryCompressed(out, cloud) != 0) {
      throw std::runtime_error("PCL could not write the binary_compressed seed");
    }
    writeFile(dir + "/binary_compressed_" + std::to_string(width), out.str());
  }
}

void imageSeeds(const std::string& dir) {
  // Every encoding index, a padded step, and one image per refusal: a short buffer, a step
  // smaller than a row.
  for (std::uint8_t e = 0; e < mmnvs_fuzz::kImageEncodingCount; ++e) {
    sensor_msgs::Image image;
    image.height = 3;
    image.width = 4;
    image.step = 4 * 4 + 2;  // room for four channels and padding
    for (std::uint32_t i = 0; i < image.step * image.height; ++i)
      image.data.push_back(static_cast<std::uint8_t>(17 * i));
    writeFile(dir + "/encoding_" + std::to_string(e), mmnvs_fuzz::bytesFromImage(image, e));
    if (e == 0) {
      sensor_msgs::Image short_data = image;
      short_data.data.resize(10);
      writeFile(dir + "/short_data", mmnvs_fuzz::bytesFromImage(short_data, e));
      sensor_msgs::Image narrow = image;
      narrow.step = 5;
      writeFile(dir + "/narrow_step", mmnvs_fuzz::bytesFromImage(narrow, e));
    }
  }
}

void npySeeds(const std::string& dir) {
  const std::vector<float> values = {1.0f, -2.0f, 0.5f, 1e-3f, 3.0f, 7.0f};
  io::writeNpy(dir + "/f4_2x3.npy", values.data(), {2, 3});
  const std::vector<std::uint8_t> mask = {0, 1, 255, 7};
  io::writeNpy(dir + "/u1_4.npy", mask.data(), {4});
  std::string f8 = io::npyHeader("<f8", {3});
  for (double v : {1.5, -0.25, 1e300})
    f8.append(reinterpret_cast<const char*>(&v), sizeof v);
  writeFile(dir + "/f8_3.npy", f8);
  std::string i8 = io::npyHeader("<i8", {1, 2});
  for (std::int64_t v : {-7LL, 1LL << 40})
    i8.append(reinterpret_cast<const char*>(&v), sizeof v);
  writeFile(dir + "/i8_1x2.npy", i8);
  // Version 2 header (4-byte length) of a scalar: shape ().
  const std::string dict = "{'descr': '<i4', 'fortran_order': False, 'shape': (), }\n";
  std::string scalar = std::string("\x93NUMPY\x02\x00", 8);
  const std::uint32_t length = static_cast<std::uint32_t>(dict.size());
  scalar.append(reinterpret_cast<const char*>(&length), 4);
  scalar += dict;
  const std::int32_t one = 42;
  scalar.append(reinterpret_cast<const char*>(&one), 4);
  writeFile(dir + "/v2_scalar.npy", scalar);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: write_fuzz_seeds DIR (creates DIR/<harness>/ for every harness)\n";
    return 2;
  }
  try {
    const std::string root = argv[1];
    makeDir(root);
    cloudSeeds(makeDir(root + "/fuzz_cloud"));
    imageSeeds(makeDir(root + "/fuzz_image"));
    kittiSeeds(makeDir(root + "/fuzz_kitti_calib"));
    cameraInfoSeeds(makeDir(root + "/fuzz_camera_info"));
    poseSeeds(makeDir(root + "/fuzz_vod_pose"));
    binSeeds(makeDir(root + "/fuzz_bin"));
    pcdSeeds(makeDir(root + "/fuzz_pcd"));
    npySeeds(makeDir(root + "/fuzz_npy"));
  } catch (const std::exception& e) {
    std::cerr << "write_fuzz_seeds: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
