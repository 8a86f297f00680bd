#pragma once
// The two halves of a CPU renderer, CpuRenderer<Kernel, Scheduler>
// (render/cpu_renderer.h), as C++20 concepts: the kernel computes pixels,
// the scheduler hands out the image's spans. Each kernel and scheduler
// header asserts its own contract, so a break fails where it is made.
#include <concepts>
#include <optional>
#include <string>

#include "core/image.h"
#include "render/render_options.h"
#include "render/renderer.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace rt {

// A kernel: built from the settings (throwing for ones it rejects), it
// reports what it is (the renderer's CSV columns), takes the scene once in
// prepare() with `slots` worker threads' scratch, the camera and target
// once per frame, and renders one span (pixels x0..x1-1 of row y) per call
// from worker `slot`; a span starts at a multiple of alignment().
template <class K>
concept CpuKernel = std::constructible_from<K, const ParallelSettings&> &&
                    requires(K kernel, const K& constKernel, const Scene& scene, const RenderOptions& options,
                             const CameraFrame& camera, Image& frame, int n) {
                      { K::kId } -> std::convertible_to<Kernel>;
                      { constKernel.lanes() } -> std::same_as<int>;
                      { constKernel.simdTarget() } -> std::same_as<std::string>;
                      { constKernel.alignment() } -> std::same_as<int>;
                      { constKernel.accelStructure() } -> std::same_as<std::optional<AccelStructureInfo>>;
                      kernel.prepare(scene, options, n);
                      kernel.beginFrame(camera, frame);
                      kernel.renderSpan(n, n, n, n);
                    };

// What a scheduler calls per span: body(slot, y, x0, x1). The archetype
// of the lambda CpuRenderer passes.
struct SpanBody {
  void operator()(int slot, int y, int x0, int x1) const;
};

// A scheduler: built from the settings, it reports its threads (the
// kernel's slots) and oneTBB split (empty where none), and calls the body
// once for every span of the image, each starting at a multiple of
// `alignment`, from worker slots below threads().
template <class S>
concept SpanScheduler =
    std::constructible_from<S, const ParallelSettings&> &&
    requires(S scheduler, const S& constScheduler, Extent extent, int alignment, const SpanBody& body) {
      { S::kId } -> std::convertible_to<Scheduler>;
      { constScheduler.threads() } -> std::same_as<int>;
      { constScheduler.grain() } -> std::same_as<std::optional<int>>;
      { constScheduler.partition() } -> std::same_as<std::optional<Partition>>;
      scheduler.forEachSpan(extent, alignment, body);
    };

}  // namespace rt
