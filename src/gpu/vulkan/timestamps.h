#pragma once
#include <cstdint>
#include <optional>

#include "gpu/vulkan/device.h"

namespace rt::gpu {

// Milliseconds between two raw timestamps: only the low `validBits` bits
// count (the counter wraps there), and each tick lasts `periodNs`.
double timestampDeltaMs(std::uint64_t start, std::uint64_t end, std::uint32_t validBits, double periodNs);

// Two timestamps around the dispatch: the device time of the compute work
// alone, which the host's wall clock cannot separate from submission and
// waiting. Inactive (no gpu_ms) on a queue without timestamps.
class DispatchTimer {
 public:
  explicit DispatchTimer(const Device& device);

  [[nodiscard]] bool active() const { return validBits_ > 0; }
  // Records the reset of both queries; before recordStart, outside any pass.
  void recordReset(const vk::raii::CommandBuffer& cb) const;
  void recordStart(const vk::raii::CommandBuffer& cb) const;
  void recordEnd(const vk::raii::CommandBuffer& cb) const;
  // The measured time, once the command buffer's fence has signalled.
  [[nodiscard]] std::optional<double> readMs() const;

 private:
  std::uint32_t validBits_;
  double periodNs_;
  vk::raii::QueryPool pool_ = nullptr;
};

}  // namespace rt::gpu
