#pragma once
// Minimal command-line parsing shared by the tools: `--name value...` options, `--flag` switches,
// a generated usage text, and errors that name the option.
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace multimodal_nvs {
namespace cli {

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Args {
 public:
  Args(std::string program, std::string summary);

  /// Declares an option taking `arity` values (-1: one or more). `fallback` is shown in --help.
  void option(const std::string& name, int arity, const std::string& help,
              const std::string& fallback = "");
  void flag(const std::string& name, const std::string& help);

  /// Parses argv; returns false if --help was given (usage already printed).
  bool parse(int argc, char** argv);

  bool has(const std::string& name) const { return values_.count(name) > 0; }
  std::string str(const std::string& name, const std::string& fallback = "") const;
  double number(const std::string& name, double fallback) const;
  int integer(const std::string& name, int fallback) const;
  const std::vector<std::string>& list(const std::string& name) const;
  std::string usage() const;

 private:
  struct Spec {
    int arity;
    std::string help, fallback;
  };
  std::string program_, summary_;
  std::vector<std::string> order_;
  std::map<std::string, Spec> specs_;
  std::map<std::string, std::vector<std::string>> values_;
};

/// Runs `body` and maps exceptions to a message on stderr and exit code 2 (usage) or 1 (input).
int runTool(const char* program, int (*body)(int, char**), int argc, char** argv);

std::string jsonEscape(const std::string& s);

}  // namespace cli
}  // namespace multimodal_nvs
