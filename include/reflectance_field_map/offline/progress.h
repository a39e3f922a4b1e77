#pragma once

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>

namespace rfm {
namespace offline {

// A one-line progress bar on stderr, drawn only when stderr is a terminal and redrawn at most
// ~10 times a second. finish() ends the line.
class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool enabled = stderrIsTerminal());
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void update(size_t done, size_t total);
  void finish();

  static bool stderrIsTerminal();

 private:
  void draw(size_t done, size_t total);

  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  size_t last_done_ = 0;
  size_t last_total_ = 0;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace offline
}  // namespace rfm
