// The progress line of `locus run` on stderr: items done / total, items per
// second, ETA, running and failed counts. Drawn only when stderr is a
// terminal; log lines are written without breaking it.
#pragma once
#include <cstddef>
#include <string>

namespace locus::runner {

class ProgressBar {
 public:
  explicit ProgressBar(size_t total);
  // Redraws on every completed item, otherwise at most 4 times a second.
  void draw(size_t done, size_t running, size_t failed, double elapsed);
  void finish();
  // Writes "locus: TEXT" on its own line without breaking the bar.
  void line(const std::string& text);

 private:
  size_t total_;
  bool on_;
  bool drawn_ = false;
  size_t last_done_ = static_cast<size_t>(-1);
  double last_draw_ = 0;
};

}  // namespace locus::runner
