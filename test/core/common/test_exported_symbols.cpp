// The package's shared libraries export none of Eigen's functions and no std::vector instantiation
// over Eigen types or Eigen's aligned allocator (cmake/local_template_symbols.map says why: they
// are compiled for another instruction set than Debian's PCL, which exports weak copies of some of
// the same instantiations, and the dynamic linker would mix the two allocation schemes).
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "tool_runner.hpp"

namespace {

bool startsWith(const std::string& s, const char* prefix) {
  return s.rfind(prefix, 0) == 0;
}

/// The rule of local_template_symbols.map, on one mangled name.
bool mustBeLocal(const std::string& symbol) {
  for (const char* prefix : {"_ZN5Eigen", "_ZNK5Eigen", "_ZZN5Eigen", "_ZGVZN5Eigen",
                             "_ZNSt6vectorIN5Eigen", "_ZNKSt6vectorIN5Eigen"}) {
    if (startsWith(symbol, prefix)) return true;
  }
  const bool vector_member = startsWith(symbol, "_ZNSt6vectorI") ||
                             startsWith(symbol, "_ZNKSt6vectorI") ||
                             startsWith(symbol, "_ZNSt12_Vector_baseI");
  return vector_member && symbol.find("N5Eigen17aligned_allocator") != std::string::npos;
}

/// Mangled names of the symbols a library defines in its dynamic symbol table.
std::vector<std::string> exportedSymbols(const std::string& library) {
  const auto result =
      multimodal_nvs::test::runCommand("nm -D --defined-only --format=posix " + library);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  std::vector<std::string> symbols;
  std::istringstream lines(result.output);
  std::string name;
  std::string rest;
  while (lines >> name && std::getline(lines, rest))
    symbols.push_back(name);
  return symbols;
}

TEST(ExportedSymbols, RuleTellsEigenInstantiationsFromTheApi) {
  EXPECT_TRUE(mustBeLocal("_ZN5Eigen8internal14aligned_mallocEm"));
  EXPECT_TRUE(mustBeLocal("_ZNSt6vectorIfN5Eigen17aligned_allocatorIfEEE17_M_default_appendEm"));
  EXPECT_TRUE(mustBeLocal("_ZNSt6vectorIN5Eigen6MatrixIdLi3ELi1ELi0ELi3ELi1EEESaIS2_EED2Ev"));
  EXPECT_FALSE(
      mustBeLocal("_ZN14multimodal_"
                  "nvs16toAngularSamplesERKSt6vectorIN5Eigen6MatrixIdLi3ELi1ELi0ELi3ELi1EEESaIS3_"
                  "EEPmPNS_10ThreadPoolE"));
  EXPECT_FALSE(mustBeLocal("_ZNSt6vectorIfSaIfEE17_M_default_appendEm"));
}

void expectEigenInstantiationsLocal(const std::string& library, int min_api_symbols) {
  const std::vector<std::string> symbols = exportedSymbols(library);
  int api = 0;
  for (const std::string& symbol : symbols) {
    EXPECT_FALSE(mustBeLocal(symbol)) << library << " exports " << symbol;
    api += startsWith(symbol, "_ZN14multimodal_nvs");
  }
  // The check read a real symbol table: the library's own API is there.
  EXPECT_GE(api, min_api_symbols) << library;
}

TEST(ExportedSymbols, CoreLibraryKeepsEigenInstantiationsLocal) {
  expectEigenInstantiationsLocal(std::string(MMNVS_TOOL_DIR) + "/../libmultimodal_nvs_core.so",
                                 100);
}

// The test binaries get the same map: test_core writes PCD fixtures through PCL.
TEST(ExportedSymbols, ThisTestBinaryKeepsEigenInstantiationsLocal) {
  // Resolved here: in nm's own process /proc/self would be nm.
  const std::vector<std::string> symbols =
      exportedSymbols(std::filesystem::read_symlink("/proc/self/exe").string());
  EXPECT_FALSE(symbols.empty());  // gtest's and PCL's inline members are there
  for (const std::string& symbol : symbols)
    EXPECT_FALSE(mustBeLocal(symbol)) << "test_core exports " << symbol;
}

// The ROS layers are built beside the core except in the sanitizer build (core and tools only).
TEST(ExportedSymbols, RosLibrariesKeepEigenInstantiationsLocal) {
  const std::string directory = std::string(MMNVS_TOOL_DIR) + "/../";
  if (multimodal_nvs::test::runCommand("test -f " + directory + "libmultimodal_nvs_ros.so")
          .exit_code != 0) {
    GTEST_SKIP() << "no ROS layer in this build (" << directory << ")";
  }
  expectEigenInstantiationsLocal(directory + "libmultimodal_nvs_ros.so", 10);
  expectEigenInstantiationsLocal(directory + "libmultimodal_nvs_nodelets.so", 1);
}

}  // namespace
