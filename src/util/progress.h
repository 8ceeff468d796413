// progress.h — the progress line on stderr: percentage, samples per second and
// time left, redrawn at most ten times a second. Silent when disabled (--quiet,
// or stderr is not a terminal).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace wp {

class Progress {
 public:
  Progress(std::string label, uint64_t totalSamples, bool enabled);
  void add(uint64_t samples);  // thread-safe
  void finish();
  static bool stderr_is_terminal();

 private:
  void draw(uint64_t done, bool final);
  std::string label_;
  uint64_t total_;
  bool enabled_;
  std::atomic<uint64_t> done_{0};
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point lastDraw_;
};

}  // namespace wp
