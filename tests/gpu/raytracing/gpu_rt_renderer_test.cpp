// The ray-tracing pipeline renderer (docs/render-model.md section 3, "The
// ray-tracing pipeline renderer"): on a device with the ray-tracing
// extensions it agrees with the sequential reference under section 8 on
// every scene the GPU tests use, both algorithms and bounce settings,
// under validation; on a device without them, the device is refused by
// name. Which of the two the test device is, Vulkan says independently.
// The driver settles exact ties (coincident spheres), not the lower index:
// there each pixel is compared with the reference that settles the ties
// as it did.
#include "gpu/raytracing/gpu_rt_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "gpu/gpu_test_support.h"
#include "gpu/raytracing/sphere_acceleration.h"
#include "gpu/vulkan/device.h"
#include "render/accel/accel_scenes.h"
#include "render/cpu_renderers.h"
#include "test_support.h"

namespace rt::test {
namespace {

constexpr long long kFrame = 25;  // an orbiting frame

// Every way the driver may settle the exact ties of `scene`: for each group
// of coincident spheres (same centre and radius), the scene with one of
// them kept. A scene without ties is its only resolution.
std::vector<Scene> tieResolutions(const Scene& scene) {
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < scene.spheres.size(); ++i) {
    const Sphere& s = scene.spheres[i];
    const auto same = std::ranges::find_if(groups, [&](const std::vector<std::size_t>& g) {
      const Sphere& t = scene.spheres[g.front()];
      return t.position == s.position && t.radius == s.radius;
    });
    if (same == groups.end()) {
      groups.push_back({i});
    } else {
      same->push_back(i);
    }
  }
  std::vector<std::vector<std::size_t>> kept{{}};  // kept sphere indices, one choice per group so far
  for (const auto& group : groups) {
    std::vector<std::vector<std::size_t>> next;
    for (const auto& choice : kept) {
      for (const std::size_t member : group) {
        next.push_back(choice);
        next.back().push_back(member);
      }
    }
    kept = std::move(next);
  }
  std::vector<Scene> scenes;
  for (auto& choice : kept) {
    std::ranges::sort(choice);
    Scene resolved = scene;
    resolved.spheres.clear();
    for (const std::size_t i : choice) resolved.spheres.push_back(scene.spheres[i]);
    scenes.push_back(std::move(resolved));
  }
  return scenes;
}

// Per pixel, the candidate closest to `actual` (largest channel difference).
Image closestPerPixel(const Image& actual, const std::vector<Image>& candidates) {
  Image closest = candidates.front();
  const auto distance = [](Rgba8 a, Rgba8 b) {
    return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
  };
  for (int y = 0; y < actual.extent().height; ++y) {
    for (int x = 0; x < actual.extent().width; ++x) {
      for (const Image& candidate : candidates) {
        if (distance(candidate.at(x, y), actual.at(x, y)) < distance(closest.at(x, y), actual.at(x, y))) {
          closest.row(y)[static_cast<std::size_t>(x)] = candidate.at(x, y);
        }
      }
    }
  }
  return closest;
}

gpu::ContextOptions rayTracingOptions() {
  const char* selector = std::getenv("RT_TEST_DEVICE");
  return {.deviceSelector = selector ? selector : "", .validation = true, .rayTracing = true};
}

// Whether the test device offers the extensions, asked of Vulkan directly
// (the plain context the other GPU tests share).
bool offersRayTracing(const gpu::Context& plain) {
  const auto extensions = plain.device().physical().enumerateDeviceExtensionProperties();
  const auto has = [&](std::string_view name) {
    return std::ranges::any_of(
        extensions, [&](const vk::ExtensionProperties& e) { return std::string_view(e.extensionName.data()) == name; });
  };
  return has(VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME) && has(VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME);
}

// One ray-tracing context per test process, with validation.
struct RayTracingNeeds {
  static gpu::ContextOptions options() { return rayTracingOptions(); }
  static bool offeredBy(const gpu::Context& plain) { return offersRayTracing(plain); }
  static constexpr const char* kWithout =
      "this device offers no ray-tracing pipeline (RayTracingDevice.IsRefusedWhereTheExtensionsAreMissing checks "
      "the refusal)";
};

class RayTracingGpuTest : public SecondContextGpuTest<RayTracingNeeds> {
 protected:
  static std::shared_ptr<gpu::Context> rayTracingContext() { return secondContext(); }
};

// Runs everywhere: a device without the extensions is refused with a
// message naming them and the renderer; one with them opens.
class RayTracingDevice : public ValidatedGpuTest {};

TEST_F(RayTracingDevice, IsRefusedWhereTheExtensionsAreMissing) {
  if (offersRayTracing(*context())) {
    EXPECT_NO_THROW(gpu::Context::open(rayTracingOptions()));
    return;
  }
  try {
    gpu::Context::open(rayTracingOptions());
    FAIL() << "a device without VK_KHR_ray_tracing_pipeline was opened for ray tracing";
  } catch (const gpu::DeviceUnavailable& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME), std::string::npos) << message;
    EXPECT_NE(message.find("ray-tracing pipeline renderer"), std::string::npos) << message;
  }
}

// NVIDIA's reorder extension is asked for only with --gpu-rt-reorder hit.
TEST_F(RayTracingDevice, TheHitReorderNeedsItsExtension) {
  gpu::ContextOptions options = rayTracingOptions();
  options.invocationReorder = true;
  const auto extensions = context()->device().physical().enumerateDeviceExtensionProperties();
  const bool offered = std::ranges::any_of(extensions, [](const vk::ExtensionProperties& e) {
    return std::string_view(e.extensionName.data()) == VK_NV_RAY_TRACING_INVOCATION_REORDER_EXTENSION_NAME;
  });
  if (offered) {
    EXPECT_NO_THROW(gpu::Context::open(options));
    return;
  }
  try {
    gpu::Context::open(options);
    FAIL() << "a device without the reorder extension was opened for the hit reorder";
  } catch (const gpu::DeviceUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find(VK_NV_RAY_TRACING_INVOCATION_REORDER_EXTENSION_NAME), std::string::npos)
        << e.what();
  }
}

// The driver's box test must not cull a sphere the float test hits: every
// box holds its sphere with room to spare, more the farther the camera.
TEST(SphereBoxes, HoldTheirSpheresWithAPadThatGrowsWithTheCameraDistance) {
  const Scene scene = loadNamedScene("random100");
  const std::vector<gpu::SphereBox> near = gpu::paddedSphereBoxes(scene.spheres, 1.0f);
  const std::vector<gpu::SphereBox> far = gpu::paddedSphereBoxes(scene.spheres, 1e5f);
  ASSERT_EQ(near.size(), scene.spheres.size());
  for (std::size_t i = 0; i < scene.spheres.size(); ++i) {
    const Sphere& s = scene.spheres[i];
    for (int a = 0; a < 3; ++a) {
      EXPECT_LT(near[i].lo[a], s.position[a] - s.radius) << i;
      EXPECT_GT(near[i].hi[a], s.position[a] + s.radius) << i;
      EXPECT_LT(far[i].lo[a], near[i].lo[a]) << i;
    }
  }
}

class GpuRtAgreement : public RayTracingGpuTest {
 protected:
  // Both algorithms and both bounce settings: the stages original
  // (two-pass, no exit) and optimized (single-pass, bounce exit), and on
  // the committed scenes the two crossed; against the sequential renderer.
  // (Each variant is a pipeline lavapipe compiles anew: minutes in all.)
  void expectAgreement(const Scene& scene, Extent extent, const std::string& label, bool crossed) {
    gpu::GpuRtRenderer renderer(rayTracingContext(), PresentMode::upload);
    SequentialRenderer reference;
    for (const Algorithm algorithm : {Algorithm::single_pass, Algorithm::two_pass}) {
      for (const bool bounce : {true, false}) {
        if (!crossed && bounce != (algorithm == Algorithm::single_pass)) continue;
        RenderOptions options{algorithm, EarlyExitSet()};
        if (bounce) options.earlyExits.add(EarlyExit::bounce);
        const Image actual = renderFrame(renderer, scene, extent, options, kFrame);
        std::vector<Image> expected;
        for (const Scene& resolved : tieResolutions(scene)) {
          expected.push_back(renderFrame(reference, resolved, extent, options, kFrame));
        }
        const ImageAgreement agreement = compareImages(actual, closestPerPixel(actual, expected));
        EXPECT_TRUE(agreement.agrees()) << label << " " << nameOf(algorithm) << (bounce ? " bounce " : " no exit ")
                                        << describe(agreement);
      }
    }
  }
};

TEST_F(GpuRtAgreement, CommittedScenesAgreeWithTheSequentialRenderer) {
  for (const char* name : kSceneNames) expectAgreement(loadNamedScene(name), {45, 29}, name, true);
}

// Exact ties, nested and touching spheres, a camera inside a huge sphere,
// a thousand spheres (tests/render/accel/accel_scenes.h).
TEST_F(GpuRtAgreement, ScenesBuiltToBreakATraversalAgreeWithTheSequentialRenderer) {
  for (const auto& [name, scene] : adversarialScenes()) expectAgreement(scene, {37, 21}, name, false);
}

// The build is reported: its time and the device memory of both levels.
TEST_F(GpuRtAgreement, ReportsTheDriversStructure) {
  gpu::GpuRtRenderer renderer(rayTracingContext(), PresentMode::none);
  renderFrame(renderer, loadNamedScene("random100"), {16, 16}, optionsForStage(Stage::optimized), kFrame);
  const RendererInfo info = renderer.info();
  ASSERT_TRUE(info.accelStructure.has_value());
  EXPECT_EQ(info.accelStructure->kind, Accel::bvh);
  EXPECT_GT(info.accelStructure->buildMs, 0.0);
  ASSERT_TRUE(info.accelStructure->deviceBytes.has_value());
  EXPECT_GT(*info.accelStructure->deviceBytes, 100u * 24u) << "at least the 100 boxes";
  EXPECT_FALSE(info.accelStructure->nodes.has_value());
  EXPECT_EQ(info.gpuRtReorder, GpuRtReorder::none);
  EXPECT_TRUE(renderer.lastGpuMs().has_value());
}

}  // namespace
}  // namespace rt::test
