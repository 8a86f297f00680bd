#include "gpu/vulkan/timestamps.h"

#include <array>

namespace rt::gpu {

double timestampDeltaMs(std::uint64_t start, std::uint64_t end, std::uint32_t validBits, double periodNs) {
  const std::uint64_t mask = validBits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << validBits) - 1;
  // Unsigned subtraction modulo 2^validBits: correct across one wrap of the counter.
  const std::uint64_t ticks = (end - start) & mask;
  return static_cast<double>(ticks) * periodNs * 1e-6;
}

DispatchTimer::DispatchTimer(const Device& device)
    : validBits_(device.info().timestampValidBits), periodNs_(device.info().timestampPeriodNs) {
  if (!active()) return;
  pool_ = vk::raii::QueryPool(device.logical(),
                              vk::QueryPoolCreateInfo{.queryType = vk::QueryType::eTimestamp, .queryCount = 2});
}

void DispatchTimer::recordReset(const vk::raii::CommandBuffer& cb) const {
  if (active()) cb.resetQueryPool(*pool_, 0, 2);
}

void DispatchTimer::recordStart(const vk::raii::CommandBuffer& cb) const {
  if (active()) cb.writeTimestamp(vk::PipelineStageFlagBits::eTopOfPipe, *pool_, 0);
}

void DispatchTimer::recordEnd(const vk::raii::CommandBuffer& cb) const {
  if (active()) cb.writeTimestamp(vk::PipelineStageFlagBits::eBottomOfPipe, *pool_, 1);
}

std::optional<double> DispatchTimer::readMs() const {
  if (!active()) return std::nullopt;
  std::array<std::uint64_t, 2> ticks{};
  // The C entry point: Vulkan-Hpp's wrapper returns a fresh vector, and the
  // Render phase must not allocate. After the fence both queries are
  // available; eWait only guards against a driver that lags.
  const auto result = static_cast<vk::Result>(pool_.getDispatcher()->vkGetQueryPoolResults(
      static_cast<VkDevice>(pool_.getDevice()), static_cast<VkQueryPool>(*pool_), 0, 2, sizeof ticks, ticks.data(),
      sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  if (result != vk::Result::eSuccess) return std::nullopt;
  return timestampDeltaMs(ticks[0], ticks[1], validBits_, periodNs_);
}

}  // namespace rt::gpu
