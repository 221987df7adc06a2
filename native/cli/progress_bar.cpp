#include "progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace bakegi::cli {

ProgressBar::ProgressBar(std::string label)
    : label_(std::move(label)),
      interactive_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()) {}

void ProgressBar::update(double fraction, const std::string& stage) {
  if (!interactive_) return;
  constexpr int kWidth = 30;
  fraction = std::clamp(fraction, 0.0, 1.0);
  const int filled = static_cast<int>(fraction * kWidth + 0.5);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string bar(static_cast<size_t>(filled), '#');
  bar.append(static_cast<size_t>(kWidth - filled), '.');
  // Remaining time by linear extrapolation, shown once there is something to extrapolate.
  char eta[32] = "";
  if (fraction > 0.02 && fraction < 1.0) {
    std::snprintf(eta, sizeof eta, ", ~%.0f s left", elapsed * (1.0 - fraction) / fraction);
  }
  std::fprintf(stderr, "\r\033[K%s [%s] %3.0f%% %.1f s%s  %s", label_.c_str(), bar.c_str(),
               fraction * 100.0, elapsed, eta, stage.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (drawn_) std::fputc('\n', stderr);
  drawn_ = false;
}

}  // namespace bakegi::cli
