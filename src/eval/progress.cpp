#include "occlusion_env/eval/progress.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

namespace occlusion_env {
namespace eval {

namespace {
constexpr int kBarWidth = 30;  // characters
}  // namespace

std::string formatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) return "?";
  const long total = std::lround(seconds);
  char text[32];
  if (total >= 3600) {
    std::snprintf(text, sizeof(text), "%ldh%02ldm", total / 3600, (total % 3600) / 60);
  } else if (total >= 60) {
    std::snprintf(text, sizeof(text), "%ldm%02lds", total / 60, total % 60);
  } else {
    std::snprintf(text, sizeof(text), "%lds", total);
  }
  return text;
}

ProgressBar::ProgressBar(std::ostream& out, int total, std::string label)
    : out_(out),
      total_(std::max(total, 1)),
      label_(std::move(label)),
      start_(std::chrono::steady_clock::now()) {}

std::string ProgressBar::render(int done, double elapsed_s, const std::string& detail) const {
  done = std::clamp(done, 0, total_);
  const double fraction = static_cast<double>(done) / total_;
  const int filled = static_cast<int>(fraction * kBarWidth);
  std::string bar(filled, '#');
  bar.resize(kBarWidth, '.');
  // The ETA assumes the remaining work goes at this run's average rate so far.
  const int done_here = done - resumed_;
  const std::string eta =
      done_here > 0 ? formatDuration(elapsed_s * (total_ - done) / done_here) : "?";
  char head[96];
  std::snprintf(head, sizeof(head), " %3d%% %d/%d elapsed %s ETA %s",
                static_cast<int>(100 * fraction), done, total_, formatDuration(elapsed_s).c_str(),
                eta.c_str());
  std::string line = label_ + " [" + bar + "]" + head;
  if (!detail.empty()) line += "  " + detail;
  return line;
}

void ProgressBar::update(int done, const std::string& detail) {
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  // \r returns to the line start, \033[K clears what a longer previous line left.
  out_ << '\r' << render(done, elapsed_s, detail) << "\033[K" << std::flush;
}

void ProgressBar::finish() {
  if (!finished_) out_ << '\n' << std::flush;
  finished_ = true;
}

}  // namespace eval
}  // namespace occlusion_env
