#pragma once
#include <memory>

#include "render/cpu_renderer.h"
#include "render/scalar/scalar_kernel.h"
#include "render/schedule/serial_scheduler.h"

namespace rt {

// The reference for correctness and speedup (the thesis' SequentialRenderer).
using SequentialRenderer = CpuRenderer<ScalarKernel, SerialScheduler>;
static_assert(SequentialRenderer::kKind == RendererKind::sequential);

// The CPU renderer `kind` names in the schema, built from its (kernel,
// scheduler) pair. Throws RendererUnavailable for a renderer that does not
// run on the CPU, LanesUnsupported or std::invalid_argument for settings
// its kernel or scheduler rejects.
// Whether this build has the CPU renderer `kind` (the Embree reference only
// with RT_EMBREE); false for renderers that do not run on the CPU.
bool cpuRendererBuilt(RendererKind kind);

std::unique_ptr<Renderer> makeCpuRenderer(RendererKind kind, const ParallelSettings& settings = {},
                                          std::unique_ptr<FrameSink> sink = nullptr);

}  // namespace rt
