#include "render/schedule/tbb_scheduler.h"

#include <oneapi/tbb/info.h>

#include <stdexcept>
#include <string>

namespace rt {
namespace {

int resolveThreads(int requested) {
  if (requested < 0)
    throw std::invalid_argument("threads must be >= 0 (0: all cores), got " + std::to_string(requested));
  return requested == ParallelSettings::kAllCores ? oneapi::tbb::info::default_concurrency() : requested;
}

int checkedGrain(int grain) {
  if (grain < 1) throw std::invalid_argument("grain must be >= 1, got " + std::to_string(grain));
  return grain;
}

}  // namespace

// The global_control caps oneTBB's whole process at `threads` (more than the
// cores too, for oversubscription experiments); the arena of the same size
// gives the workers the slot indices 0..threads-1 that index the scratch.
TbbScheduler::TbbScheduler(int threads, int grain, Partition partition)
    : threads_(resolveThreads(threads)),
      grain_(checkedGrain(grain)),
      partition_(partition),
      limit_(oneapi::tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads_)),
      arena_(threads_) {
  // Start the arena and oneTBB's workers now, not lazily inside the first
  // frame's render(): that first use allocates, and it would be timed.
  arena_.initialize();
  arena_.execute([this] { oneapi::tbb::parallel_for(0, threads_, [](int) {}); });
}

}  // namespace rt
