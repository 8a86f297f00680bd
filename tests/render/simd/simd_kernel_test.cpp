// The SIMD and threaded renderers against the sequential reference (docs/render-model.md
// section 8): every mode x algorithm x early-exit set x lanes, on every
// scene at an even and an odd size, on every Highway target this CPU runs.
#include "render/simd/simd_kernel.h"

#include <gtest/gtest.h>

#include <map>
#include <tuple>
#include <type_traits>

#include "render/cpu_renderers.h"
#include "render/render_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

constexpr Extent kSizes[] = {{96, 64}, {101, 37}};  // 101: partial packets at every lane count
constexpr long long kFrames[] = {0, 30};
constexpr long long kFrame = 30;
constexpr int kLaneRequests[] = {4, ParallelSettings::kNativeLanes};

EarlyExitSet only(EarlyExit e) {
  EarlyExitSet s;
  s.add(e);
  return s;
}

// none, each one alone, all: the SIMD kernel has a variant for each.
const EarlyExitSet kExitSets[] = {EarlyExitSet(), only(EarlyExit::bounce), only(EarlyExit::sphere),
                                  only(EarlyExit::discriminant), EarlyExitSet::all()};

// The sequential images, rendered once per process and reused by every
// mode, lane count and exit set that shares the same bounce setting.
class References {
 public:
  const Image& get(const std::string& sceneName, const Scene& scene, Extent extent, long long frame,
                   RenderOptions options) {
    options.earlyExits = options.earlyExits.has(EarlyExit::bounce) ? only(EarlyExit::bounce) : EarlyExitSet();
    const auto key =
        std::make_tuple(sceneName, extent.width, extent.height, frame, options.algorithm, options.earlyExits.mask());
    auto it = images_.find(key);
    if (it == images_.end()) {
      SequentialRenderer sequential;
      it = images_.emplace(key, test::renderFrame(sequential, scene, extent, options, frame)).first;
    }
    return it->second;
  }

 private:
  std::map<std::tuple<std::string, int, int, long long, Algorithm, unsigned>, Image> images_;
};

References& references() {
  static References refs;
  return refs;
}

std::string laneName(int lanes) { return lanes == ParallelSettings::kNativeLanes ? "native" : std::to_string(lanes); }

// Every scene x size x frame x algorithm x exit set with one renderer.
void expectAgreementEverywhere(Renderer& renderer, std::span<const EarlyExitSet> exitSets, const std::string& label) {
  for (const char* name : test::kSceneNames) {
    const Scene scene = test::loadNamedScene(name);
    for (const Extent extent : kSizes) {
      for (const long long frame : kFrames) {
        for (const Algorithm algorithm : {Algorithm::single_pass, Algorithm::two_pass}) {
          for (const EarlyExitSet exits : exitSets) {
            const RenderOptions options{algorithm, exits};
            const Image& want = references().get(name, scene, extent, frame, options);
            const Image got = test::renderFrame(renderer, scene, extent, options, frame);
            const ImageAgreement a = compareImages(got, want);
            EXPECT_TRUE(a.agrees()) << label << " " << name << " " << extent.width << "x" << extent.height << " frame "
                                    << frame << " " << nameOf(algorithm) << " early_exit=" << exits.toString() << ": "
                                    << test::describe(a);
          }
        }
      }
    }
  }
}

using TargetAndMode = std::tuple<std::int64_t, RendererKind>;

class SimdAgreement : public ::testing::TestWithParam<TargetAndMode> {};

TEST_P(SimdAgreement, AgreesWithSequential) {
  const auto [target, mode] = GetParam();
  const simd::ScopedTargetOverride force(target);
  for (const int lanes : kLaneRequests) {
    ParallelSettings settings;
    settings.lanes = lanes;
    const bool scalarTarget = simd::dispatchedKernels().f32.nativeLanes < 4;
    if (lanes == 4 && scalarTarget) {
      EXPECT_THROW(makeCpuRenderer(mode, settings), LanesUnsupported);
      continue;
    }
    const auto renderer = makeCpuRenderer(mode, settings);
    ASSERT_EQ(renderer->info().simdTarget, simd::targetName(target)) << "the forced target must be the one used";
    expectAgreementEverywhere(*renderer, kExitSets, std::string(nameOf(mode)) + " lanes=" + laneName(lanes));
  }
}

INSTANTIATE_TEST_SUITE_P(EveryTarget, SimdAgreement,
                         ::testing::Combine(::testing::ValuesIn(simd::availableTargets()),
                                            ::testing::Values(RendererKind::simd_tbb, RendererKind::simd_only)),
                         [](const ::testing::TestParamInfo<TargetAndMode>& p) {
                           return simd::targetName(std::get<0>(p.param)) + "_" +
                                  std::string(nameOf(std::get<1>(p.param)));
                         });

// tbb_only runs the scalar kernel, which has the bounce exit only; the
// other two exits must not change its image either.
TEST(TbbOnlyAgreement, AgreesWithSequential) {
  const auto renderer = makeCpuRenderer(RendererKind::tbb_only);
  expectAgreementEverywhere(*renderer, kExitSets, "tbb_only");
}

// main() answers RendererUnavailable with exit code 2, the lanes error included.
static_assert(std::is_base_of_v<RendererUnavailable, LanesUnsupported>);

// --lanes 4/8/16 exist exactly where the target's vectors hold that many floats.
TEST(Lanes, FollowTheTargetOnEveryTarget) {
  for (const std::int64_t target : simd::availableTargets()) {
    const simd::ScopedTargetOverride force(target);
    const int native = simd::dispatchedKernels().f32.nativeLanes;
    ParallelSettings settings;
    EXPECT_EQ(makeCpuRenderer(RendererKind::simd_only, settings)->info().lanes, native);
    for (const int lanes : schema::kLaneWidths) {
      settings.lanes = lanes;
      if (lanes <= native) {
        EXPECT_EQ(makeCpuRenderer(RendererKind::simd_only, settings)->info().lanes, lanes) << simd::targetName(target);
      } else {
        EXPECT_THROW(makeCpuRenderer(RendererKind::simd_only, settings), LanesUnsupported) << simd::targetName(target);
      }
    }
  }
  // The override is lifted again: dispatch is back to the best target.
  EXPECT_EQ(simd::dispatchedKernels().target, simd::availableTargets().front());
}

TEST(Lanes, NativeIsTheBestTargetsWidth) {
  const auto targets = simd::availableTargets();
  ASSERT_FALSE(targets.empty());
  const RendererInfo info = makeCpuRenderer(RendererKind::simd_tbb)->info();
  EXPECT_EQ(info.simdTarget, simd::targetName(targets.front()));
  EXPECT_EQ(info.lanes, simd::dispatchedKernels().f32.nativeLanes);
}

// Images narrower than one packet, and every remainder of 16 lanes.
TEST(PartialPackets, NarrowImagesAgreeWithSequential) {
  const Scene scene = test::loadNamedScene("default");
  const RenderOptions options = optionsForStage(Stage::optimized);
  SequentialRenderer sequential;
  const auto renderer = makeCpuRenderer(RendererKind::simd_only);
  for (int width = 1; width <= 17; ++width) {
    const Extent extent{width, 5};
    const Image want = test::renderFrame(sequential, scene, extent, options, kFrame);
    const Image got = test::renderFrame(*renderer, scene, extent, options, kFrame);
    const ImageAgreement a = compareImages(got, want);
    EXPECT_LE(a.maxChannelDifference, 2) << "width " << width << ": " << test::describe(a);
  }
}

// The scenes' shininess is whole (32); a fractional one takes exp(e log x).
TEST(Shading, FractionalShininessAgreesWithSequential) {
  Scene scene = test::loadNamedScene("default");
  scene.render.shininess = 12.5f;
  SequentialRenderer sequential;
  const RenderOptions options = optionsForStage(Stage::optimized);
  const Image want = test::renderFrame(sequential, scene, {96, 64}, options, kFrame);
  for (const std::int64_t target : simd::availableTargets()) {
    const simd::ScopedTargetOverride force(target);
    const auto renderer = makeCpuRenderer(RendererKind::simd_only);
    const ImageAgreement a = compareImages(test::renderFrame(*renderer, scene, {96, 64}, options, kFrame), want);
    EXPECT_TRUE(a.agrees()) << simd::targetName(target) << ": " << test::describe(a);
  }
}

}  // namespace
}  // namespace rt
