#pragma once
// What the CPU renderers' two Vulkan FrameSinks (makeFrameUpload's and
// makeSwapchainUpload's) share: where they upload to (the context's device,
// or the window's swapchain), the device resources a staged upload needs, made
// for one frame extent and again only when it changes, and the checks of
// FrameSink's contract against that extent. Each sink says how its
// resources are replaced and what a frame's upload and readback record.
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "core/image.h"
#include "render/frame_sink.h"

namespace rt::gpu {

// `Resources` has an `extent` member: the extent it was made for.
template <typename Destination, typename Resources>
class StagedUpload : public FrameSink {
 public:
  void prepare(Extent extent) final {
    if (resources_ && resources_->extent == extent) return;
    replace(resources_, extent);
  }

  void present(std::span<const Rgba8> frame) final {
    Resources& r = prepared();
    if (frame.size() != r.extent.pixelCount()) throw std::logic_error(name_ + ": frame size differs from the extent");
    upload(r, frame);
  }

  void readBack(Image& target) final {
    Resources& r = prepared();
    if (target.extent() != r.extent) throw std::logic_error(name_ + ": target extent differs");
    download(r, target);
  }

 protected:
  // `name` names the sink in its errors. Throws std::invalid_argument
  // without a `destination` (`destinationKind` says what it is).
  StagedUpload(std::string name, std::shared_ptr<Destination> destination, std::string_view destinationKind)
      : name_(std::move(name)), destination_(std::move(destination)) {
    if (!destination_) throw std::invalid_argument(name_ + " needs " + std::string(destinationKind));
  }

  [[nodiscard]] Destination& destination() const { return *destination_; }

  // Drops `resources` (none before the first prepare()) and makes them for `extent`.
  virtual void replace(std::unique_ptr<Resources>& resources, Extent extent) = 0;
  // The Present phase of `frame`, whose size has been checked.
  virtual void upload(Resources& r, std::span<const Rgba8> frame) = 0;
  // The frame last presented into `target`, whose extent has been checked.
  virtual void download(Resources& r, Image& target) = 0;

 private:
  Resources& prepared() {
    if (!resources_) throw std::logic_error(name_ + ": prepare() was not called");
    return *resources_;
  }

  std::string name_;
  std::shared_ptr<Destination> destination_;  // declared before the resources, so it outlives them
  std::unique_ptr<Resources> resources_;
};

}  // namespace rt::gpu
