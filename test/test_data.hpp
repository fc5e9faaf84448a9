#pragma once
// Locating the real VoD data and the reference outputs for tests. They live outside the repository
// (MMNVS_DATA_DIR, default <repo>/../shared/data). When CI=true a missing directory is a failure;
// otherwise the test is skipped with a message saying what is missing.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdlib>
#include <string>

namespace multimodal_nvs {
namespace test {

inline std::string dataDir() {
  const char* env = std::getenv("MMNVS_DATA_DIR");
  return env != nullptr && *env != '\0' ? std::string(env) : std::string(MMNVS_DATA_DIR_DEFAULT);
}

/// ../shared/reference beside the data directory (MMNVS_REFERENCE_DIR overrides).
inline std::string referenceDir() {
  const char* env = std::getenv("MMNVS_REFERENCE_DIR");
  if (env != nullptr && *env != '\0') return env;
  return dataDir() + "/../reference";
}

inline bool pathExists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

inline bool runningInCi() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string(ci) == "true";
}

}  // namespace test
}  // namespace multimodal_nvs

/// Skips (locally) or fails (CI=true) the current test when `path` does not exist.
#define MMNVS_REQUIRE_DATA(path)                                                            \
  do {                                                                                      \
    const std::string mmnvs_required_path = (path);                                         \
    if (!::multimodal_nvs::test::pathExists(mmnvs_required_path)) {                         \
      if (::multimodal_nvs::test::runningInCi()) {                                          \
        FAIL() << "CI=true but required data is missing: " << mmnvs_required_path           \
               << " (set MMNVS_DATA_DIR)";                                                  \
      }                                                                                     \
      GTEST_SKIP() << "data not found: " << mmnvs_required_path                             \
                   << " (set MMNVS_DATA_DIR to the shared data directory)";                 \
    }                                                                                       \
  } while (0)
