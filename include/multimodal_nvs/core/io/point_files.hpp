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
  kPcd,       ///< PCD v0.7 (ascii, binary, binary_compressed), fields x y z (F4 or F8) + others
};

PointFormat parsePointFormat(const std::string& name);  ///< radar|lidar|vod7|xyzi|xyz|xyz3|pcd
int floatsPerRecord(PointFormat format);                ///< 0 for PCD

/// Reads x, y, z of every point. Throws InputError naming the file and the reason: missing,
/// truncated, size not a multiple of the record, a PCD that PCL's reader would misread.
/// Non-finite values of a .bin are kept (the core drops and counts them); a PCD's are dropped here
/// (PCL marks the missing returns of an organised cloud with NaN).
std::vector<Eigen::Vector3f> readPoints(const std::string& path, PointFormat format);
/// A PCD file's bytes through PCL's PCDReader (pcd_reader.cpp), after io::checkPcdLayout; every
/// field is checked against the point size before x, y, z are read.
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
