#include "cli.hpp"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/json_text.hpp"

namespace multimodal_nvs {
namespace cli {

Args::Args(std::string program, std::string summary)
    : program_(std::move(program)), summary_(std::move(summary)) {}

void Args::option(const std::string& name, int arity, const std::string& help,
                  const std::string& fallback) {
  order_.push_back(name);
  specs_[name] = {arity, help, fallback};
}

void Args::flag(const std::string& name, const std::string& help) {
  option(name, 0, help);
}

bool Args::parse(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << usage();
      return false;
    }
    const auto it = specs_.find(arg.rfind("--", 0) == 0 ? arg.substr(2) : std::string());
    if (it == specs_.end()) throw UsageError("unknown argument '" + arg + "'");
    std::vector<std::string>& v = values_[it->first];
    v.clear();
    const int arity = it->second.arity;
    while (i + 1 < argc && (arity < 0 || static_cast<int>(v.size()) < arity)) {
      const std::string next = argv[i + 1];
      if (arity < 0 && next.rfind("--", 0) == 0) break;
      v.push_back(next);
      ++i;
    }
    if ((arity > 0 && static_cast<int>(v.size()) != arity) || (arity < 0 && v.empty())) {
      throw UsageError(
          "--" + it->first + " expects " +
          (arity < 0 ? std::string("at least one value") : std::to_string(arity) + " value(s)"));
    }
  }
  return true;
}

std::string Args::str(const std::string& name, const std::string& fallback) const {
  const auto it = values_.find(name);
  return it == values_.end() || it->second.empty() ? fallback : it->second[0];
}

double Args::number(const std::string& name, double fallback) const {
  if (!has(name)) return fallback;
  const std::string s = str(name);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0' || std::isnan(v)) {
    throw UsageError("--" + name + ": '" + s + "' is not a number");
  }
  return v;
}

int Args::integer(const std::string& name, int fallback) const {
  if (!has(name)) return fallback;
  const std::string s = str(name);
  char* end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0') throw UsageError("--" + name + ": '" + s + "' is not an integer");
  return static_cast<int>(v);
}

const std::vector<std::string>& Args::list(const std::string& name) const {
  static const std::vector<std::string> empty;
  const auto it = values_.find(name);
  return it == values_.end() ? empty : it->second;
}

std::string Args::usage() const {
  std::ostringstream out;
  out << "usage: " << program_ << " [options]\n" << summary_ << "\n\noptions:\n";
  for (const auto& name : order_) {
    const Spec& s = specs_.at(name);
    out << "  --" << name;
    if (s.arity == 1) out << " X";
    if (s.arity > 1) out << " X×" << s.arity;
    if (s.arity < 0) out << " X...";
    out << "\n      " << s.help;
    if (!s.fallback.empty()) out << " (default: " << s.fallback << ")";
    out << "\n";
  }
  return out.str();
}

int runTool(const char* program, int (*body)(int, char**), int argc, char** argv) {
  try {
    return body(argc, argv);
  } catch (const UsageError& e) {
    std::cerr << program << ": " << e.what() << " (see --help)\n";
    return 2;
  } catch (const InputError& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return 1;
  }
}

std::string jsonEscape(const std::string& s) {
  return ::multimodal_nvs::jsonEscape(s);
}

}  // namespace cli
}  // namespace multimodal_nvs
