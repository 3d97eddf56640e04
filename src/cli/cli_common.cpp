#include "cli_common.h"

#include <chrono>
#include <cstdio>
#include <string>

#include <unistd.h>

namespace medspheres::cli {

std::string non_negative(const std::string& text) {
  return text.rfind('-', 0) == 0 ? "must be an integer >= 0, got " + text : std::string();
}

std::string non_empty(const std::string& text) {
  return text.empty() ? "must not be empty" : std::string();
}

bool stderr_is_terminal() {
  return ::isatty(STDERR_FILENO) == 1;
}

ProgressBar::ProgressBar(bool enabled) : enabled_(enabled && stderr_is_terminal()) {}

ProgressBar::~ProgressBar() {
  finish();
}

void ProgressBar::update(const std::string& stage, std::size_t done, std::size_t total) {
  if (!enabled_ || total == 0) return;
  const double now =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (done < total && now - last_ < 0.1) return;
  last_ = now;
  constexpr int kWidth = 30;
  const double f = static_cast<double>(done) / static_cast<double>(total);
  const int filled = static_cast<int>(f * kWidth);
  std::fprintf(stderr, "\r%-26s [%s%s] %3d%%", stage.c_str(), std::string(filled, '#').c_str(),
               std::string(kWidth - filled, ' ').c_str(), static_cast<int>(100 * f));
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (!drawn_) return;
  std::fprintf(stderr, "\r%*s\r", 70, "");
  std::fflush(stderr);
  drawn_ = false;
}

}  // namespace medspheres::cli
