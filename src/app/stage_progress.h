#pragma once
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <ostream>
#include <string>
#include <thread>

namespace rt {

// One slow stage of start-up (loading the scene, preparing the renderer):
// once it has run `patience`, a line says what is happening; when it ends,
// a second line gives its time. A stage that ends sooner prints nothing, so
// small scenes start as quietly as before. A watcher thread waits beside the
// stage; the stage itself does not report.
class StageProgress {
 public:
  static constexpr std::chrono::milliseconds kPatience{1000};

  // `what` ("loading scenes/x.json (125 MB)") goes after "raytracer: ";
  // null `out` (--quiet) prints nothing, but the stage is still timed.
  StageProgress(std::string what, std::ostream* out, std::chrono::milliseconds patience = kPatience);
  StageProgress(const StageProgress&) = delete;
  StageProgress& operator=(const StageProgress&) = delete;
  ~StageProgress();

  // Ends the stage: its wall time in milliseconds, printed as "done in 2.4 s"
  // where the start was announced.
  double finish();

 private:
  void watch(std::chrono::milliseconds patience);
  void stop();

  std::string what_;
  std::ostream* out_;
  std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool finished_ = false;
  bool announced_ = false;
  std::thread watcher_;
};

}  // namespace rt
