#include "multimodal_nvs/core/io/camera_info_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace io {
namespace {

// yaml-cpp's own exceptions (parse errors, bad conversions) are turned into InputError naming the
// key, so that callers see one error type for every malformed file.
double number(const YAML::Node& node, const std::string& source, const std::string& key) {
  double v = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, v) || !std::isfinite(v)) {
    throw InputError(source + ": '" + key + "' is not a finite number");
  }
  return v;
}

int dimension(const YAML::Node& root, const std::string& source, const std::string& key) {
  const YAML::Node node = root[key];
  if (!node) throw InputError(source + ": no '" + key + "'");
  const double v = number(node, source, key);
  if (v < 1.0 || v > 1e6 || v != std::floor(v)) {
    throw InputError(source + ": '" + key + "' is not a positive image dimension");
  }
  return static_cast<int>(v);
}

/// A `{rows, cols, data}` matrix; `rows`/`cols` must match `data`'s length when given.
std::vector<double> matrixData(const YAML::Node& root, const std::string& source,
                               const std::string& key) {
  const YAML::Node node = root[key];
  if (!node || !node.IsMap()) throw InputError(source + ": no '" + key + "' matrix");
  const YAML::Node data = node["data"];
  if (!data || !data.IsSequence()) throw InputError(source + ": '" + key + "' has no data list");
  std::vector<double> values;
  values.reserve(data.size());
  for (std::size_t i = 0; i < data.size(); ++i)
    values.push_back(number(data[i], source, key + ".data"));
  if (node["rows"] && node["cols"]) {
    const double rows = number(node["rows"], source, key + ".rows");
    const double cols = number(node["cols"], source, key + ".cols");
    if (rows * cols != static_cast<double>(values.size())) {
      // Printed as the file wrote them: rows/cols may be any finite number here, far outside int.
      std::ostringstream message;
      message << source << ": '" << key << "' says " << rows << "x" << cols << " but has "
              << values.size() << " numbers";
      throw InputError(message.str());
    }
  }
  return values;
}

}  // namespace

CameraInfoYaml parseCameraInfoYaml(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(source + ": not YAML (" + e.msg + ", line " + std::to_string(e.mark.line + 1) +
                     ")");
  }
  if (!root.IsMap()) throw InputError(source + ": not a camera_info YAML (no key: value map)");
  CameraInfoYaml out;
  try {
    out.size.width = dimension(root, source, "image_width");
    out.size.height = dimension(root, source, "image_height");
    const std::vector<double> k = matrixData(root, source, "camera_matrix");
    if (k.size() != 9) throw InputError(source + ": 'camera_matrix' needs 9 numbers");
    if (k[1] != 0.0 || k[3] != 0.0 || k[6] != 0.0 || k[7] != 0.0 || k[8] != 1.0) {
      throw InputError(source + ": 'camera_matrix' is not [fx 0 cx; 0 fy cy; 0 0 1]");
    }
    out.intrinsics = PinholeIntrinsics{k[0], k[4], k[2], k[5]};
    out.intrinsics.validate(source + " (camera_matrix)");
    if (root["rectification_matrix"]) {
      const std::vector<double> r = matrixData(root, source, "rectification_matrix");
      const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
      if (r.size() != 9 || !std::equal(r.begin(), r.end(), identity)) {
        throw InputError(source +
                         ": 'rectification_matrix' is not identity (rectified stereo cameras are "
                         "not supported)");
      }
    }
    std::string model;
    if (const YAML::Node m = root["distortion_model"]) {
      if (!m.IsScalar()) throw InputError(source + ": 'distortion_model' is not a name");
      model = m.Scalar();
    }
    std::vector<double> d;
    if (root["distortion_coefficients"]) d = matrixData(root, source, "distortion_coefficients");
    out.intrinsics.distortion = LensDistortion::fromRos(model, d, source);
  } catch (const YAML::Exception& e) {
    throw InputError(source + ": malformed camera_info (" + e.msg + ")");
  }
  return out;
}

CameraInfoYaml readCameraInfoYaml(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open camera_info YAML (" + std::strerror(errno) + ")");
  std::stringstream ss;
  ss << in.rdbuf();
  return parseCameraInfoYaml(ss.str(), path);
}

PinholeIntrinsics frameIntrinsics(const KittiCalib& calib, const std::string& camera_info_path,
                                  const ImageSize& image) {
  if (camera_info_path.empty()) return calib.intrinsics();
  const CameraInfoYaml info = readCameraInfoYaml(camera_info_path);
  if (!(info.size == image)) {
    throw InputError(camera_info_path + ": camera_info is " + std::to_string(info.size.width) +
                     "x" + std::to_string(info.size.height) + " but the image is " +
                     std::to_string(image.width) + "x" + std::to_string(image.height));
  }
  return info.intrinsics;
}

}  // namespace io
}  // namespace multimodal_nvs
