#pragma once
// Raw point scans: KITTI / View-of-Delft float32 records and PCD files.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace multimodal_nvs {
namespace io {

/// Record layouts of raw float32 scans.
enum class PointFormat {
  kVodRadar,  ///< 7 floats: x, y, z, RCS, v_r, v_r_compensated, time
  kXyzi,      ///< 4 floats: x, y, z, intensity (KITTI/VoD LiDAR)
  kXyz,       ///< 3 floats: x, y, z
  kPcd,       ///< PCD v0.7, ascii or binary, fields x y z (F4 or F8) plus any others
};

PointFormat parsePointFormat(const std::string& name);  ///< radar|lidar|vod7|xyzi|xyz|xyz3|pcd
int floatsPerRecord(PointFormat format);                ///< 0 for PCD

/// Reads x, y, z of every point (non-finite values are kept; the core drops and counts them).
/// Throws InputError naming the file: missing, truncated, size not a multiple of the record, bad
/// PCD header.
std::vector<Eigen::Vector3f> readPoints(const std::string& path, PointFormat format);
std::vector<Eigen::Vector3f> parsePcd(const std::string& bytes, const std::string& source);
std::vector<Eigen::Vector3f> parseFloatRecords(const std::string& bytes, int floats_per_record,
                                               const std::string& source);

/// Raw records (all fields) of a float32 .bin file, row-major count x floats_per_record.
std::vector<float> readFloatRecords(const std::string& path, int floats_per_record);
std::vector<float> parseFloatRecordValues(const std::string& bytes, int floats_per_record,
                                          const std::string& source);
void writeFloatRecords(const std::string& path, const std::vector<float>& values);

}  // namespace io
}  // namespace multimodal_nvs
