#include "render/cpu_renderers.h"

#include <string>

#include "render/schedule/tbb_scheduler.h"
#include "render/simd/packet_kernels.h"
#include "render/simd/simd_kernel.h"
#ifdef RT_HAVE_EMBREE
#include "render/embree/embree_kernel.h"
#endif

namespace rt {
namespace {

template <class Kernel>
std::unique_ptr<Renderer> withScheduler(Scheduler scheduler, const ParallelSettings& settings,
                                        std::unique_ptr<FrameSink> sink) {
  switch (scheduler) {
    case Scheduler::serial: return std::make_unique<CpuRenderer<Kernel, SerialScheduler>>(settings, std::move(sink));
    case Scheduler::tbb: return std::make_unique<CpuRenderer<Kernel, TbbScheduler>>(settings, std::move(sink));
  }
  throw std::logic_error("unknown scheduler");
}

// The Embree kernel pairs with oneTBB only (the schema has no serial row
// for it), so only that pair is instantiated; without RT_EMBREE it is
// absent from this build, and asking for it is the user's error (exit 2).
std::unique_ptr<Renderer> makeEmbreeRenderer(RendererKind kind, const ParallelSettings& settings,
                                             std::unique_ptr<FrameSink> sink) {
#ifdef RT_HAVE_EMBREE
  static_assert(CpuRenderer<EmbreeKernel, TbbScheduler>::kKind == RendererKind::embree);
  if (kind != RendererKind::embree) throw std::logic_error("the Embree kernel runs only as renderer 'embree'");
  return std::make_unique<CpuRenderer<EmbreeKernel, TbbScheduler>>(settings, std::move(sink));
#else
  (void)settings;
  (void)sink;
  throw RendererUnavailable("renderer '" + std::string(nameOf(kind)) +
                            "' is not built in this version (configure with RT_EMBREE=ON; Debian: libembree-dev)");
#endif
}

}  // namespace

std::vector<SimdBuildTarget> simdBuildTargets() {
  std::vector<SimdBuildTarget> targets;
  for (const simd::CompiledTarget& t : simd::compiledTargets()) {
    targets.push_back({simd::targetName(t.target), t.nativeF16});
  }
  return targets;
}

bool cpuRendererBuilt(RendererKind kind) {
  const auto& pair = definitionOf(kind);
  if (!pair.kernel) return false;
#ifndef RT_HAVE_EMBREE
  if (*pair.kernel == Kernel::embree) return false;
#endif
  return true;
}

std::unique_ptr<Renderer> makeCpuRenderer(RendererKind kind, const ParallelSettings& settings,
                                          std::unique_ptr<FrameSink> sink) {
  const schema::RendererDefinition& pair = definitionOf(kind);
  if (!pair.kernel || !pair.scheduler) {
    throw RendererUnavailable("renderer '" + std::string(nameOf(kind)) + "' does not run on the CPU");
  }
  switch (*pair.kernel) {
    case Kernel::scalar: return withScheduler<ScalarKernel>(*pair.scheduler, settings, std::move(sink));
    case Kernel::simd: return withScheduler<SimdKernel>(*pair.scheduler, settings, std::move(sink));
    case Kernel::embree: return makeEmbreeRenderer(kind, settings, std::move(sink));
  }
  throw std::logic_error("unknown kernel");
}

}  // namespace rt
