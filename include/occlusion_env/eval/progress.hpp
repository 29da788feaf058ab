// A one-line terminal progress bar with the elapsed time and an ETA, redrawn in place.
#pragma once

#include <chrono>
#include <iosfwd>
#include <string>

namespace occlusion_env {
namespace eval {

/// "1h02m", "3m07s", "12s".
std::string formatDuration(double seconds);

class ProgressBar {
 public:
  /// Draws to `out` (normally std::cerr); `total` > 0 units of work.
  ProgressBar(std::ostream& out, int total, std::string label);
  /// Sets the completed count and redraws, with `detail` (e.g. the current agent) at the end.
  void update(int done, const std::string& detail = "");
  /// Work that was done before this bar started (a resumed run): it counts in the fraction, not
  /// in the rate behind the ETA. Call before the first update().
  void resumeFrom(int done) { resumed_ = done; }
  /// Ends the line.
  void finish();
  /// The line update() would draw after `elapsed_s` seconds (for tests).
  std::string render(int done, double elapsed_s, const std::string& detail) const;

 private:
  std::ostream& out_;
  int total_;
  std::string label_;
  std::chrono::steady_clock::time_point start_;
  int resumed_ = 0;  // done before start_
  bool finished_ = false;
};

}  // namespace eval
}  // namespace occlusion_env
