#include "progress.hpp"

#include <unistd.h>

#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace multimodal_nvs {
namespace cli {
namespace {

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

}  // namespace

Progress::Progress(std::string tool, int total, std::string unit, bool quiet)
    : tool_(std::move(tool)),
      unit_(std::move(unit)),
      total_(total > 0 ? total : 0),
      quiet_(quiet),
      terminal_(isatty(fileno(stderr)) != 0),
      start_(std::chrono::steady_clock::now()) {}

double Progress::seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::step(const std::string& label) {
  ++done_;
  if (quiet_ || total_ == 0) return;
  const double elapsed = seconds();
  if (terminal_) {
    const int width = 30, filled = done_ * width / total_;
    const double remaining = done_ < total_ ? elapsed / done_ * (total_ - done_) : 0.0;
    std::cerr << "\r" << tool_ << " [" << std::string(filled, '#')
              << std::string(width - filled, '.') << "] " << done_ << "/" << total_ << " " << unit_
              << ", " << fixed(elapsed, 1) << " s";
    if (done_ < total_) std::cerr << ", ~" << fixed(remaining, 0) << " s left  ";
    std::cerr << (done_ == total_ ? "\n" : "") << std::flush;
  } else {
    std::cerr << tool_ << ": " << done_ << "/" << total_ << " " << unit_
              << (label.empty() ? "" : " (" + label + ")") << " at " << fixed(elapsed, 2) << " s\n";
  }
}

void Progress::finish() {
  if (quiet_ || done_ == 0) return;
  const double s = seconds();
  std::cerr << tool_ << ": " << done_ << " " << unit_ << " in " << fixed(s, 2) << " s ("
            << fixed(done_ / s, 2) << " " << unit_ << "/s, " << fixed(1000.0 * s / done_, 0)
            << " ms per item)\n";
}

}  // namespace cli
}  // namespace multimodal_nvs
