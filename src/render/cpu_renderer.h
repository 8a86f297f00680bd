#pragma once
// A CPU renderer is a (kernel, scheduler) pair, as the schema's renderer
// rows name them: the kernel says how pixels are computed (scalar, SIMD
// packets), the scheduler how the image's spans are handed out (serial,
// oneTBB). As in oneTBB's tachyon, the strategies differ only in their
// scheduling file (render/schedule/); everything else is shared.
#include <algorithm>
#include <memory>
#include <stdexcept>

#include "render/cpu_contracts.h"
#include "render/frame_sink.h"
#include "render/renderer.h"

namespace rt {

// The contracts of both halves are the concepts of render/cpu_contracts.h.
// The per-span call is a template, inlined: no virtual call in the frame.
template <CpuKernel Kernel, SpanScheduler Scheduler>
class CpuRenderer final : public Renderer {
 public:
  static constexpr RendererKind kKind = rendererFor(Kernel::kId, Scheduler::kId);

  // Throws what the kernel and the scheduler throw for settings they reject
  // (the kernel first: an unsupported lane width is the more specific error).
  // `sink` receives each presented frame; none keeps it in the working buffer.
  explicit CpuRenderer(const ParallelSettings& settings = {}, std::unique_ptr<FrameSink> sink = nullptr)
      : kernel_(settings), scheduler_(settings), sink_(std::move(sink)) {}

  [[nodiscard]] RendererInfo info() const override {
    RendererInfo info{kKind,
                      scheduler_.threads(),
                      kernel_.lanes(),
                      kernel_.simdTarget(),
                      scheduler_.grain(),
                      scheduler_.partition(),
                      kernel_.accelStructure()};
    if constexpr (requires { kernel_.traversal(); }) {  // the SIMD kernel's walk of the BVH
      info.traversal = kernel_.traversal();
      info.hybridThreshold = kernel_.hybridThreshold();
    }
    if constexpr (requires { kernel_.precision(); }) info.precision = kernel_.precision();  // the SIMD kernel's f16
    return info;
  }

  [[nodiscard]] std::optional<LaneCounters> lastCounters() const override {
    if constexpr (requires { kernel_.counters(); }) {
      return kernel_.counters();
    } else {
      return std::nullopt;
    }
  }

  void prepare(const Scene& scene, Extent extent, const RenderOptions& options) override {
    if (frame_.extent() != extent) frame_ = Image(extent);
    kernel_.prepare(scene, options, scheduler_.threads());
    if (sink_) sink_->prepare(extent);
  }

  void render(const CameraFrame& camera) override {
    kernel_.beginFrame(camera, frame_);
    scheduler_.forEachSpan(frame_.extent(), kernel_.alignment(),
                           [this](int slot, int y, int x0, int x1) { kernel_.renderSpan(slot, y, x0, x1); });
  }

  // The thesis' StagingData: the working buffer goes to the sink, if any.
  void present() override {
    if (sink_) sink_->present(frame_.pixels());
  }

  void readPresented(Image& target) override {
    if (target.extent() != frame_.extent())
      throw std::logic_error("readPresented: target extent differs from the frame's");
    if (sink_) {
      sink_->readBack(target);  // what really reached the sink
    } else {
      std::ranges::copy(frame_.pixels(), target.pixels().begin());
    }
  }

 private:
  Kernel kernel_;
  Scheduler scheduler_;
  std::unique_ptr<FrameSink> sink_;
  Image frame_;  // the working buffer
};

}  // namespace rt
