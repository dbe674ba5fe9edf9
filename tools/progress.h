// A one-line progress display on stderr for long work: redrawn in place on a
// terminal, one line per stage (start and end) otherwise (logs, CI).
#ifndef GROUNDLINE_TOOLS_PROGRESS_H_
#define GROUNDLINE_TOOLS_PROGRESS_H_

#include <unistd.h>

#include <cstdio>
#include <string>
#include <string_view>

namespace groundline::tools {

class ProgressLine {
 public:
  explicit ProgressLine(std::string prefix)
      : prefix_(std::move(prefix)), interactive_(::isatty(STDERR_FILENO) == 1) {}

  // fraction in [0, 1].
  void Update(std::string_view stage, double fraction) {
    const int percent = static_cast<int>(fraction * 100.0 + 0.5);
    if (interactive_) {
      constexpr int kBarWidth = 30;
      const int filled = percent * kBarWidth / 100;
      std::fprintf(stderr, "\r%s %-9.*s [%-*s] %3d%%", prefix_.c_str(),
                   static_cast<int>(stage.size()), stage.data(), kBarWidth,
                   std::string(static_cast<std::size_t>(filled), '#').c_str(), percent);
      if (percent >= 100) std::fputc('\n', stderr);
      std::fflush(stderr);
      return;
    }
    if (stage != stage_ || percent >= 100) {
      std::fprintf(stderr, "%s %.*s %d%%\n", prefix_.c_str(), static_cast<int>(stage.size()),
                   stage.data(), percent);
      stage_ = std::string(stage);
    }
  }

 private:
  std::string prefix_;
  bool interactive_;
  std::string stage_;
};

}  // namespace groundline::tools

#endif  // GROUNDLINE_TOOLS_PROGRESS_H_
