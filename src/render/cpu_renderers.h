#pragma once
#include <memory>
#include <string>
#include <vector>

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

// A Highway target the SIMD kernel was compiled for, as the run metadata
// records it (build.simd_targets): what this build holds, whatever this CPU
// runs, so that a test can tell a target left out from one the CPU lacks.
struct SimdBuildTarget {
  std::string name;    // Highway's name: "AVX3_SPR", "AVX2", "NEON", ...
  bool halfPrecision;  // whether its kernels compute in f16 (docs/render-model.md section 10)
};

// This build's SIMD targets, best first.
std::vector<SimdBuildTarget> simdBuildTargets();

std::unique_ptr<Renderer> makeCpuRenderer(RendererKind kind, const ParallelSettings& settings = {},
                                          std::unique_ptr<FrameSink> sink = nullptr);

}  // namespace rt
