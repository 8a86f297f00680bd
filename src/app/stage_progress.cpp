#include "app/stage_progress.h"

#include <cstdio>

namespace rt {

StageProgress::StageProgress(std::string what, std::ostream* out, std::chrono::milliseconds patience)
    : what_(std::move(what)), out_(out), start_(std::chrono::steady_clock::now()) {
  if (out_ != nullptr) watcher_ = std::thread([this, patience] { watch(patience); });
}

// A stage left by an exception says nothing more: the error will.
StageProgress::~StageProgress() { stop(); }

void StageProgress::watch(std::chrono::milliseconds patience) {
  std::unique_lock lock(mutex_);
  if (wake_.wait_until(lock, start_ + patience, [this] { return finished_; })) return;
  *out_ << "raytracer: " << what_ << " ...\n" << std::flush;
  announced_ = true;
}

void StageProgress::stop() {
  {
    const std::lock_guard lock(mutex_);
    finished_ = true;
  }
  wake_.notify_one();
  if (watcher_.joinable()) watcher_.join();
}

double StageProgress::finish() {
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  stop();
  if (announced_) {
    announced_ = false;
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.1f s", ms / 1000.0);
    *out_ << "raytracer: " << what_ << ": done in " << seconds << "\n" << std::flush;
  }
  return ms;
}

}  // namespace rt
