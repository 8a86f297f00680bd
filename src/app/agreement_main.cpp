// rt_agreement: how far one renderer's frame 0 is from the double-precision
// reference (docs/render-model.md section 8), with the breakdown of the
// rule at scale: compareImages' figures for the full frame and for the
// camera rays alone (maxDepth 1), and the differing pixels split into those
// whose camera ray differs and those only reflected rays change, by size.
// Takes the raytracer's options (scene, --renderer, --accel, --stage,
// --width, --height, --threads, --device...); renders no measured frames.
//   build/release/rt_agreement scenes/random10000.json --renderer gpu --accel bvh --width 960 --height 540
#include <chrono>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "app/cli.h"
#include "app/device_setup.h"
#include "app/program_main.h"
#include "app/renderer_factory.h"
#include "render/scalar/double_reference.h"
#include "scene/scene_loader.h"

namespace {

struct FramePair {
  rt::Image full;
  rt::Image primary;  // maxDepth 1: camera rays only
};

rt::Image renderFrameZero(rt::Renderer& renderer, const rt::Scene& scene, const rt::RunConfig& config) {
  renderer.prepare(scene, config.extent, config.options);
  renderer.render(rt::cameraAtFrame(scene.camera, 0));
  renderer.present();
  rt::Image image(config.extent);
  renderer.readPresented(image);
  return image;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string sizes(const rt::DifferenceSizes& d) {
  std::ostringstream out;
  out << d.pixels << " (max " << d.max << "/255; by size";
  int lower = 3;
  for (std::size_t i = 0; i < std::size(d.bands); ++i) {
    out << " " << lower << "-" << rt::DifferenceSizes::kBandUpper[i] << ":" << d.bands[i];
    lower = rt::DifferenceSizes::kBandUpper[i] + 1;
  }
  return out.str() + ")";
}

void report(const rt::AgreementBreakdown& b, double rendererSeconds, double referenceSeconds) {
  const auto share = [&](std::size_t n) { return 100.0 * static_cast<double>(n) / static_cast<double>(b.pixelCount); };
  std::cout << std::fixed << std::setprecision(3) << "full frame: within 2/255 "
            << 100.0 * b.full.fractionWithinTolerance << " %, PSNR " << b.full.psnrDb << " dB, max "
            << b.full.maxChannelDifference << "/255\n"
            << "camera rays only (maxDepth 1): within 2/255 " << 100.0 * b.primary.fractionWithinTolerance
            << " %, PSNR " << b.primary.psnrDb << " dB, max " << b.primary.maxChannelDifference << "/255\n"
            << "differing pixels whose camera ray differs: " << share(b.primaryRay.pixels)
            << " % = " << sizes(b.primaryRay) << "\n"
            << "differing pixels only reflected rays change: " << share(b.reflectedOnly.pixels)
            << " % = " << sizes(b.reflectedOnly) << "\n"
            << "within the weighted tolerance (2/255, or 2/255 + 255 x reflectivity " << b.reflectivity
            << " where only reflected rays differ): " << share(b.withinWeightedTolerance) << " %\n"
            << "section 8 rule: " << (b.full.agrees() ? "agrees" : "disagrees")
            << "; rule at scale: " << (b.agreesAtScale() ? "agrees" : "disagrees") << "\n"
            << "seconds: renderer (prepare and both frames) " << rendererSeconds
            << ", double reference (BVH build and the full frame) " << referenceSeconds << "\n";
}

int run(const rt::RunConfig& config) {
  rt::Scene scene = rt::loadScene(config.scenePath);
  const rt::DeviceSetup setup = rt::setUpDevice(config, std::cerr);
  FramePair got;
  FramePair want;
  auto start = std::chrono::steady_clock::now();
  {
    auto renderer = rt::makeRenderer(config.renderer, config.parallel, setup.present);
    got.full = renderFrameZero(*renderer, scene, config);
    const int maxDepth = scene.render.maxDepth;
    scene.render.maxDepth = 1;
    got.primary = renderFrameZero(*renderer, scene, config);
    scene.render.maxDepth = maxDepth;
  }
  const double rendererSeconds = secondsSince(start);
  start = std::chrono::steady_clock::now();
  const rt::DoubleReference reference(scene);
  const rt::CameraFrame camera = rt::cameraAtFrame(scene.camera, 0);
  want.full = reference.render(camera, config.extent, config.options);
  const double referenceSeconds = secondsSince(start);
  scene.render.maxDepth = 1;
  want.primary = reference.render(camera, config.extent, config.options);
  std::cout << config.scenePath.string() << " " << rt::nameOf(config.renderer) << " --accel "
            << rt::nameOf(config.options.accel) << " " << config.extent.width << "x" << config.extent.height
            << " frame 0 (" << scene.spheres.size() << " spheres)\n";
  report(rt::breakDownAgreement(got.full, want.full, got.primary, want.primary, scene.render.reflectivity),
         rendererSeconds, referenceSeconds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return rt::runProgram("rt_agreement", argc, argv, run); }
