#pragma once
// The tools' command lines on CLI11 (Debian's libcli11-dev): one place that sets the help layout
// (required inputs first, defaults shown, an example), the number checks every tool shares, and the
// mapping of errors to exit codes (2: usage, 1: input).
#include <CLI/CLI.hpp>
#include <stdexcept>
#include <string>

namespace multimodal_nvs {
namespace cli {

/// Bad command line (exit code 2). CLI11's own parse errors are turned into this.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Option groups of --help, listed in this order when each tool declares its groups in this order.
constexpr const char* kRequired = "Required inputs";
constexpr const char* kInputs = "Inputs";
constexpr const char* kOutput = "Output";
constexpr const char* kModel = "Depth model";
constexpr const char* kGround = "ground_gp model";
constexpr const char* kOptions = "Options";

/// The tools' conventions on `app`: defaults captured from the bound variables and shown, the
/// example as the footer. Call before declaring options.
void setUp(CLI::App& app, const std::string& example);

/// Parses argv. Returns false when --help was given (the help is printed). Any parse error (unknown
/// option, malformed or out-of-range number, missing value) throws UsageError naming the option.
bool parse(CLI::App& app, int argc, char** argv);

/// Whether the option was given on the command line.
bool given(const CLI::App& app, const std::string& name);

/// Number checks that name the option in their message (CLI11 prefixes it).
CLI::Validator atLeast(double minimum);
CLI::Validator positive();
/// Rejects NaN and +-inf (CLI11 accepts "nan" and "inf" for floating-point options).
CLI::Validator finite();

/// --pose-key, declared alike in every tool: which transform of a VoD pose file to read. Only the
/// default differs, by what the pose is used for (`used_for` says it in --help).
void declarePoseKeyOption(CLI::App& app, std::string& key, const std::string& group,
                          const std::string& used_for);

/// Runs `body` and maps exceptions to a message on stderr and exit code 2 (usage) or 1 (input).
int runTool(const char* program, int (*body)(int, char**), int argc, char** argv);

}  // namespace cli
}  // namespace multimodal_nvs
