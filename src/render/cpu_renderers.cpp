#include <string>

#include "render/cpu_renderers.h"
#include "render/schedule/tbb_scheduler.h"
#include "render/simd/simd_kernel.h"

namespace rt {
namespace {

template <class Kernel>
std::unique_ptr<Renderer> withScheduler(Scheduler scheduler, const ParallelSettings& settings,
                                        std::unique_ptr<FrameSink> sink) {
  switch (scheduler) {
    case Scheduler::serial:
      return std::make_unique<CpuRenderer<Kernel, SerialScheduler>>(settings, std::move(sink));
    case Scheduler::tbb:
      return std::make_unique<CpuRenderer<Kernel, TbbScheduler>>(settings, std::move(sink));
  }
  throw std::logic_error("unknown scheduler");
}

}  // namespace

std::unique_ptr<Renderer> makeCpuRenderer(RendererKind kind, const ParallelSettings& settings,
                                          std::unique_ptr<FrameSink> sink) {
  const schema::RendererDefinition& pair = definitionOf(kind);
  if (!pair.kernel || !pair.scheduler) {
    throw RendererUnavailable("renderer '" + std::string(nameOf(kind)) + "' does not run on the CPU");
  }
  switch (*pair.kernel) {
    case Kernel::scalar:
      return withScheduler<ScalarKernel>(*pair.scheduler, settings, std::move(sink));
    case Kernel::simd:
      return withScheduler<SimdKernel>(*pair.scheduler, settings, std::move(sink));
  }
  throw std::logic_error("unknown kernel");
}

}  // namespace rt
