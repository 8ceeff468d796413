#include "util/progress.h"

#include <cstdio>
#include <unistd.h>

namespace wp {

Progress::Progress(std::string label, uint64_t totalSamples, bool enabled)
    : label_(std::move(label)), total_(totalSamples), enabled_(enabled),
      start_(std::chrono::steady_clock::now()), lastDraw_(start_) {}

bool Progress::stderr_is_terminal() {
  return ::isatty(STDERR_FILENO) != 0;
}

void Progress::add(uint64_t samples) {
  uint64_t done = done_.fetch_add(samples) + samples;
  if (!enabled_) return;
  auto now = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || now - lastDraw_ < std::chrono::milliseconds(100)) return;
  lastDraw_ = now;
  draw(done, false);
}

void Progress::finish() {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  draw(done_.load(), true);
  std::fputc('\n', stderr);
}

void Progress::draw(uint64_t done, bool final) {
  double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  double rate = elapsed > 0.0 ? double(done) / elapsed : 0.0;
  double pct = total_ ? 100.0 * double(done) / double(total_) : 100.0;
  double left = rate > 0.0 ? double(total_ - std::min(done, total_)) / rate : 0.0;
  std::fprintf(stderr, "\r%s %5.1f%%  %.2f Msamples/s  %s %.1f s   ", label_.c_str(), pct, rate * 1e-6,
               final ? "took" : "left", final ? elapsed : left);
  std::fflush(stderr);
}

}  // namespace wp
