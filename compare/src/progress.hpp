// A progress bar on stderr, shown only when stderr is a terminal.
#pragma once
#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace lockstep::cli {

class Progress {
 public:
  Progress(long long total, bool enabled) : total_(total), enabled_(enabled && isatty(STDERR_FILENO) != 0) {}
  ~Progress() { finish(); }
  void update(long long done) {
    if (!enabled_ || total_ <= 0) return;
    const auto now = std::chrono::steady_clock::now();
    if (done < total_ && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const int width = 40;
    const int filled = static_cast<int>(width * done / total_);
    std::fprintf(stderr, "\r[%.*s%*s] %lld/%lld frames", filled, "########################################",
                 width - filled, "", done, total_);
    std::fflush(stderr);
    shown_ = true;
  }
  void finish() {
    if (shown_) std::fprintf(stderr, "\n");
    shown_ = false;
  }

 private:
  long long total_;
  bool enabled_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace lockstep::cli
