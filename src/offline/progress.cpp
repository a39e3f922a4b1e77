#include "reflectance_field_map/offline/progress.h"

#include <unistd.h>

#include <algorithm>

namespace rfm {
namespace offline {

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() {
  finish();
}

bool ProgressBar::stderrIsTerminal() {
  return isatty(STDERR_FILENO) == 1;
}

void ProgressBar::update(size_t done, size_t total) {
  if (!enabled_) return;
  last_done_ = done;
  last_total_ = total;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && done < total && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  draw(done, total);
}

void ProgressBar::draw(size_t done, size_t total) {
  constexpr int kWidth = 40;
  const double fraction = total > 0 ? std::min(1.0, static_cast<double>(done) / total) : 1.0;
  const int filled = static_cast<int>(fraction * kWidth);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string bar(static_cast<size_t>(filled), '#');
  bar.append(static_cast<size_t>(kWidth - filled), '.');
  std::fprintf(stderr, "\r%-10s [%s] %3d%% %zu/%zu %.1fs", label_.c_str(), bar.c_str(),
               static_cast<int>(fraction * 100.0), done, total, seconds);
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (!enabled_ || !drawn_) return;
  draw(last_done_, last_total_);
  std::fputc('\n', stderr);
  std::fflush(stderr);
  drawn_ = false;
  enabled_ = false;
}

}  // namespace offline
}  // namespace rfm
