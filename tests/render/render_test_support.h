#pragma once
// Renders one frame with any Renderer, as the frame loop would.
#include "core/image.h"
#include "render/renderer.h"
#include "scene/camera.h"

namespace rt::test {

inline Image renderFrame(Renderer& renderer, const Scene& scene, Extent extent, const RenderOptions& options,
                         long long frame) {
  renderer.prepare(scene, extent, options);
  renderer.render(cameraAtFrame(scene.camera, frame));
  renderer.present();
  Image out(extent);
  renderer.readPresented(out);
  return out;
}

// gtest prints this when an agreement check fails.
inline std::string describe(const ImageAgreement& a) {
  return "within tolerance " + std::to_string(100.0 * a.fractionWithinTolerance) + " %, PSNR " +
         std::to_string(a.psnrDb) + " dB, max channel difference " + std::to_string(a.maxChannelDifference);
}

}  // namespace rt::test
