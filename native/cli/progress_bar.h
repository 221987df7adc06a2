// A one-line text progress bar on stderr, redrawn in place when stderr is a terminal;
// otherwise (logs, pipes) it stays silent so that logs are not flooded with redraws.
#pragma once

#include <chrono>
#include <string>

namespace bakegi::cli {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  void update(double fraction, const std::string& stage);
  void finish();  // ends the line

 private:
  std::string label_;
  bool interactive_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace bakegi::cli
