#include "cli.hpp"

#include <cmath>
#include <iostream>
#include <sstream>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace cli {

void setUp(CLI::App& app, const std::string& example) {
  app.option_defaults()->always_capture_default();
  app.get_formatter()->column_width(34);
  app.footer("Example:\n  " + example);
}

bool parse(CLI::App& app, int argc, char** argv) {
  // Declared last so that --help sits under the tool's own groups, not above the required inputs.
  app.set_help_flag();
  app.set_help_flag("-h,--help", "print this help and exit")->group(kOptions);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return false;
  } catch (const CLI::ConversionError& e) {
    // CLI11 says "Could not convert: --threads = 4294967297"; say what is wrong with the value.
    const std::string what = e.what(), prefix = "Could not convert: ";
    const std::size_t eq = what.find(" = ");
    if (what.rfind(prefix, 0) == 0 && eq != std::string::npos) {
      throw UsageError(what.substr(prefix.size(), eq - prefix.size()) + ": '" +
                       what.substr(eq + 3) +
                       "' is not a number of the option's type, or out of its range");
    }
    throw UsageError(what);
  } catch (const CLI::ParseError& e) {
    throw UsageError(e.what());
  }
  return true;
}

bool given(const CLI::App& app, const std::string& name) {
  return app.count(name) > 0;
}

namespace {

std::string describe(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// The option's text as a double, or NaN when it is not a number.
double asNumber(const std::string& text) {
  double v = 0.0;
  return CLI::detail::lexical_cast(text, v) ? v : std::nan("");
}

std::string notANumber(const std::string& text) {
  return "'" + text + "' is not a number";
}

}  // namespace

CLI::Validator atLeast(double minimum) {
  return CLI::Validator(
      [minimum](std::string& text) {
        const double v = asNumber(text);
        if (std::isnan(v)) return notANumber(text);
        return v >= minimum ? std::string() : "must be >= " + describe(minimum) + ", got " + text;
      },
      ">=" + describe(minimum));
}

CLI::Validator positive() {
  return CLI::Validator(
      [](std::string& text) {
        const double v = asNumber(text);
        if (std::isnan(v)) return notANumber(text);
        return v > 0.0 && std::isfinite(v) ? std::string() : "must be > 0, got " + text;
      },
      ">0");
}

CLI::Validator finite() {
  return CLI::Validator(
      [](std::string& text) {
        const double v = asNumber(text);
        if (std::isnan(v)) return notANumber(text);
        return std::isfinite(v) ? std::string() : "must be a finite number, got " + text;
      },
      "");
}

void declarePoseKeyOption(CLI::App& app, std::string& key, const std::string& group,
                          const std::string& used_for) {
  app.add_option(
         "--pose-key", key,
         "which transform of the VoD pose files (odomToCamera|mapToCamera|UTMToCamera) " + used_for)
      ->group(group);
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

}  // namespace cli
}  // namespace multimodal_nvs
