// The progress line of `locus run` (see progress_bar.hpp).
#include "tools/runner/progress_bar.hpp"

#include <unistd.h>

#include <cstdio>

namespace locus::runner {
namespace {

std::string human_seconds(double s) {
  if (!(s >= 0) || s > 1e7) return "?";
  char buf[32];
  if (s < 60) {
    std::snprintf(buf, sizeof buf, "%.0fs", s);
  } else if (s < 3600) {
    std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s) / 3600, static_cast<int>(s) / 60 % 60);
  }
  return buf;
}

}  // namespace

ProgressBar::ProgressBar(size_t total) : total_(total), on_(::isatty(STDERR_FILENO) == 1) {}

void ProgressBar::draw(size_t done, size_t running, size_t failed, double elapsed) {
  if (!on_) return;
  if (done == last_done_ && elapsed - last_draw_ < 0.25) return;
  last_done_ = done;
  last_draw_ = elapsed;
  constexpr int kWidth = 30;
  const int fill = total_ ? static_cast<int>(kWidth * done / total_) : kWidth;
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0;
  const std::string eta =
      done > 0 && done < total_ ? human_seconds((total_ - done) / rate) : (done == total_ ? "0s" : "?");
  std::fprintf(stderr, "\r[%s%s] %zu/%zu  %.2f items/s  ETA %s  running %zu  failed %zu \x1b[K",
               std::string(static_cast<size_t>(fill), '#').c_str(),
               std::string(static_cast<size_t>(kWidth - fill), '.').c_str(), done, total_, rate, eta.c_str(), running,
               failed);
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (on_ && drawn_) std::fputc('\n', stderr);
  drawn_ = false;
}

void ProgressBar::line(const std::string& text) {
  if (on_ && drawn_) std::fputs("\r\x1b[K", stderr);
  std::fprintf(stderr, "locus: %s\n", text.c_str());
}

}  // namespace locus::runner
