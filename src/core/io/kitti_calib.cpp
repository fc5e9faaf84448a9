#include "multimodal_nvs/core/io/kitti_calib.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <Eigen/Core>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace io {

KittiCalib parseKittiCalib(const std::string& text, const std::string& source) {
  KittiCalib calib;
  calib.source = source;
  std::istringstream lines(text);
  std::string line;
  int line_number = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string key = line.substr(0, colon);
    key.erase(0, key.find_first_not_of(" \t"));
    key.erase(key.find_last_not_of(" \t\r") + 1);
    if (key.empty()) continue;
    std::vector<double> values;
    std::istringstream numbers(line.substr(colon + 1));
    std::string token;
    while (numbers >> token) {
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(token.c_str(), &end);
      if (end != token.c_str() + token.size() || errno == ERANGE) {
        throw InputError(source + ":" + std::to_string(line_number) + ": '" + key +
                         "' has an unparsable number '" + token + "'");
      }
      values.push_back(v);
    }
    calib.entries[key] = std::move(values);
  }
  return calib;
}

KittiCalib readKittiCalib(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open calibration file (" + std::strerror(errno) + ")");
  std::stringstream ss;
  ss << in.rdbuf();
  return parseKittiCalib(ss.str(), path);
}

const std::vector<double>& KittiCalib::numbers(const std::string& key, std::size_t count) const {
  const auto it = entries.find(key);
  if (it == entries.end()) throw InputError(source + ": no '" + key + ":' entry");
  if (it->second.size() < count) {
    throw InputError(source + ": '" + key + "' has " + std::to_string(it->second.size()) +
                     " numbers, expected " + std::to_string(count));
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(it->second[i])) {
      throw InputError(source + ": '" + key + "' contains a non-finite number");
    }
  }
  return it->second;
}

PinholeIntrinsics KittiCalib::intrinsics(const std::string& key) const {
  const auto& p = numbers(key, 12);
  PinholeIntrinsics k{p[0], p[5], p[2], p[6]};
  k.validate(source + " (" + key + ")");
  return k;
}

SensorToCamera KittiCalib::matrix3x4(const std::string& key) const {
  const auto& t = numbers(key, 12);
  SensorToCamera m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c)
      m(r, c) = t[r * 4 + c];
  }
  return m;
}

SensorToCamera KittiCalib::sensorToCamera(const std::string& projection) const {
  SensorToCamera m = matrix3x4("Tr_velo_to_cam");
  // Each step only when it changes something, so that VoD-style files (identity R0_rect, [K | 0])
  // keep their extrinsic bit for bit.
  if (entries.count("R0_rect")) {
    const auto& r0 = numbers("R0_rect", 9);
    const Eigen::Matrix3d rect =
        Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(r0.data());
    if (!rect.isIdentity(0.0)) m = rect * m;
  }
  const PinholeIntrinsics k = intrinsics(projection);
  const auto& p = numbers(projection, 12);
  if (p[3] != 0.0 || p[7] != 0.0 || p[11] != 0.0) {
    // P = K [I | t]  =>  t = K⁻¹ P[:, 3] (K upper triangular with zero skew).
    const double tz = p[11];
    m(0, 3) += (p[3] - k.cx * tz) / k.fx;
    m(1, 3) += (p[7] - k.cy * tz) / k.fy;
    m(2, 3) += tz;
  }
  if (!m.allFinite()) {
    throw InputError(source + ": R0_rect · Tr_velo_to_cam with " + projection +
                     "'s translation overflows");
  }
  return m;
}

void writeKittiCalib(const std::string& path, const PinholeIntrinsics& k,
                     const SensorToCamera& sensor_to_camera) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot open for writing");
  out << std::setprecision(12);
  for (int cam = 0; cam < 4; ++cam) {
    out << 'P' << cam << ": " << k.fx << " 0.0 " << k.cx << " 0.0 0.0 " << k.fy << ' ' << k.cy
        << " 0.0 0.0 0.0 1.0 0.0\n";
  }
  out << "R0_rect: 1.0 0.0 0.0 0.0 1.0 0.0 0.0 0.0 1.0\nTr_velo_to_cam:";
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c)
      out << ' ' << sensor_to_camera(r, c);
  }
  out << "\nTr_imu_to_velo:\n";
  if (!out) throw InputError(path + ": write failed");
}

}  // namespace io
}  // namespace multimodal_nvs
