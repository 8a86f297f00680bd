#include "app/cli.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <vector>

#include "app/cli_test_support.h"

namespace rt {
namespace {

using test::parse;
using test::parseOk;

int exitCode(std::initializer_list<const char*> args) {
  auto result = parse(args);
  const auto* exit = std::get_if<CliExit>(&result);
  return exit == nullptr ? -1 : exit->code;
}

TEST(Cli, DefaultsAreTheThesisHabit) {
  const RunConfig c = parseOk({});
  EXPECT_EQ(c.renderer, RendererKind::sequential);
  EXPECT_EQ(c.scenePath, "scenes/default.json");
  EXPECT_EQ(c.extent, (Extent{800, 600}));
  EXPECT_EQ(c.options.algorithm, Algorithm::single_pass);
  EXPECT_EQ(c.options.earlyExits, EarlyExitSet::all());
  EXPECT_FALSE(c.csvPath);
}

TEST(Cli, RendererFlagAndSceneAsInTheThesis) {
  const RunConfig c = parseOk({"--sequential", "scenes/random20.json"});
  EXPECT_EQ(c.renderer, RendererKind::sequential);
  EXPECT_EQ(c.scenePath, "scenes/random20.json");
  EXPECT_EQ(parseOk({"--gpu"}).renderer, RendererKind::gpu);
  EXPECT_EQ(parseOk({"--simd"}).renderer, RendererKind::simd_tbb);
}

TEST(Cli, StagesSetAlgorithmAndEarlyExits) {
  const RunConfig original = parseOk({"--stage", "original"});
  EXPECT_EQ(original.options.algorithm, Algorithm::two_pass);
  EXPECT_EQ(original.options.earlyExits, EarlyExitSet());
  const RunConfig single = parseOk({"--stage", "single-pass"});
  EXPECT_EQ(single.options.algorithm, Algorithm::single_pass);
  EXPECT_EQ(single.options.earlyExits.toString(), "bounce");
}

TEST(Cli, AlgorithmAndEarlyExitLists) {
  const RunConfig c = parseOk({"--algorithm", "two-pass", "--early-exit", "sphere,bounce"});
  EXPECT_EQ(c.options.algorithm, Algorithm::two_pass);
  EXPECT_EQ(c.options.earlyExits.toString(), "bounce+sphere");
  EXPECT_EQ(parseOk({"--early-exit", "none"}).options.earlyExits, EarlyExitSet());
}

// --accel picks the structure; Embree always walks its own BVH, so that is
// what its runs record, and asking it for brute force is refused.
TEST(Cli, AccelChoosesTheStructureAndEmbreeKeepsItsOwn) {
  EXPECT_EQ(parseOk({}).options.accel, Accel::none);
  EXPECT_EQ(parseOk({"--simd", "--accel", "bvh"}).options.accel, Accel::bvh);
  EXPECT_EQ(parseOk({"--embree"}).options.accel, Accel::bvh);
  EXPECT_EQ(parseOk({"--embree", "--accel", "bvh"}).options.accel, Accel::bvh);
  const CliExit refused = test::parseFails({"--embree", "--accel", "none"});
  EXPECT_EQ(refused.code, kExitBadInput);
  EXPECT_NE(refused.error.find("always uses its own bvh"), std::string::npos) << refused.error;
}

// The traversal axis and the counters belong to the SIMD kernel
// (schema: traversals); the default walk is the packet one.
TEST(Cli, TraversalThresholdAndCountersFillTheRenderOptions) {
  const RunConfig plain = parseOk({"--simd", "--accel", "bvh"});
  EXPECT_EQ(plain.options.traversal, Traversal::packet);
  EXPECT_EQ(plain.options.hybridThreshold, RenderOptions::kDefaultHybridThreshold);
  EXPECT_FALSE(plain.options.counters);
  EXPECT_EQ(parseOk({"--simd-only", "--accel", "bvh", "--traversal", "single"}).options.traversal, Traversal::single);
  const RunConfig hybrid =
      parseOk({"--simd", "--accel", "bvh", "--traversal", "hybrid", "--hybrid-threshold", "6", "--stage", "original"});
  EXPECT_EQ(hybrid.options.traversal, Traversal::hybrid);
  EXPECT_EQ(hybrid.options.hybridThreshold, 6) << "--stage must not reset it";
  EXPECT_EQ(hybrid.options.algorithm, Algorithm::two_pass);
  EXPECT_EQ(parseOk({"--simd", "--accel", "bvh", "--traversal", "hybrid"}).options.hybridThreshold,
            RenderOptions::kDefaultHybridThreshold);
  EXPECT_TRUE(parseOk({"--simd", "--counters"}).options.counters) << "brute force counts too";
  EXPECT_TRUE(parseOk({"--simd-only", "--accel", "bvh", "--traversal", "single", "--counters"}).options.counters);
}

// Any traversal, packet too: another renderer's run, or one by brute
// force, would record a traversal it did not walk (schema: axes).
TEST(Cli, TraversalNeedsASimdRendererAndABvh) {
  for (const char* renderer : {"--sequential", "--tbb-only", "--gpu", "--embree"}) {
    for (const char* traversal : {"single", "packet"}) {
      const CliExit refused = test::parseFails({renderer, "--accel", "bvh", "--traversal", traversal});
      EXPECT_EQ(refused.code, kExitBadInput) << renderer;
      EXPECT_NE(refused.error.find("does not take --traversal; --traversal applies to --simd and --simd-only"),
                std::string::npos)
          << refused.error;
    }
  }
  for (const char* traversal : {"hybrid", "packet"}) {
    const CliExit bruteForce = test::parseFails({"--simd", "--traversal", traversal});
    EXPECT_EQ(bruteForce.code, kExitBadInput);
    EXPECT_NE(
        bruteForce.error.find("--traversal " + std::string(traversal) + " needs --accel bvh or auto (accel is none)"),
        std::string::npos)
        << bruteForce.error;
  }
  EXPECT_EQ(parseOk({"--simd", "--accel", "auto", "--traversal", "single"}).options.traversal, Traversal::single);
  EXPECT_EQ(exitCode({"--simd", "--accel", "bvh", "--traversal", "diagonal"}), kExitBadInput);
}

TEST(Cli, HybridThresholdIsPositiveAndOnlyForHybrid) {
  for (const char* traversal : {"packet", "single"}) {
    const CliExit refused =
        test::parseFails({"--simd", "--accel", "bvh", "--traversal", traversal, "--hybrid-threshold", "4"});
    EXPECT_EQ(refused.code, kExitBadInput) << traversal;
    EXPECT_NE(refused.error.find("--hybrid-threshold 4 needs --traversal hybrid (traversal is " +
                                 std::string(traversal) + ")"),
              std::string::npos)
        << refused.error;
  }
  EXPECT_EQ(exitCode({"--simd", "--accel", "bvh", "--hybrid-threshold", "4"}), kExitBadInput) << "packet by default";
  for (const char* bad : {"0", "-3", "2.5", "4x", "99999999999"}) {
    const CliExit refused =
        test::parseFails({"--simd", "--accel", "bvh", "--traversal", "hybrid", "--hybrid-threshold", bad});
    EXPECT_EQ(refused.code, kExitBadInput) << bad;
    EXPECT_NE(refused.error.find("--hybrid-threshold: expected a positive integer, got '" + std::string(bad) + "'"),
              std::string::npos)
        << refused.error;
  }
}

// The SIMD kernel and the GPU renderer count (schema frame_csv: the counter
// columns); the scalar renderers and Embree do not.
TEST(Cli, CountersNeedACountingRenderer) {
  for (const char* renderer : {"--sequential", "--tbb-only", "--embree"}) {
    const CliExit refused = test::parseFails({renderer, "--counters"});
    EXPECT_EQ(refused.code, kExitBadInput) << renderer;
    EXPECT_NE(refused.error.find("does not take --counters; --counters applies to --simd, --simd-only and --gpu"),
              std::string::npos)
        << refused.error;
  }
  EXPECT_TRUE(parseOk({"--gpu", "--counters"}).options.counters);
  EXPECT_TRUE(parseOk({"--gpu", "--accel", "bvh", "--gpu-bvh", "wide", "--counters"}).options.counters);
  EXPECT_FALSE(parseOk({"--gpu"}).options.counters);
}

// Every name of the GPU renderer's walk parses to its enum value (schema:
// gpu_bvhs); the default is RenderOptions'.
TEST(Cli, GpuBvhFillsTheRenderOptions) {
  const RunConfig plain = parseOk({"--gpu", "--accel", "bvh"});
  EXPECT_EQ(plain.options.gpuBvh, GpuBvh::binary);
  for (std::size_t i = 0; i < schema::kGpuBvhNames.size(); ++i) {
    const std::string name(schema::kGpuBvhNames[i]);
    EXPECT_EQ(parseOk({"--gpu", "--accel", "bvh", "--gpu-bvh", name.c_str()}).options.gpuBvh, static_cast<GpuBvh>(i))
        << name;
  }
  const RunConfig wide = parseOk({"--gpu", "--accel", "bvh", "--gpu-bvh", "wide", "--stage", "original"});
  EXPECT_EQ(wide.options.gpuBvh, GpuBvh::wide) << "--stage must not reset it";
  EXPECT_EQ(wide.options.algorithm, Algorithm::two_pass);
}

// A CPU renderer would record a GPU setting it ignored: the option is
// refused there, its default value too.
TEST(Cli, GpuBvhNeedsTheGpuRenderer) {
  for (const char* renderer : {"--sequential", "--simd", "--simd-only", "--tbb-only", "--embree", "--gpu-rt"}) {
    for (const char* bvh : {"binary", "wide"}) {
      const CliExit refused = test::parseFails({renderer, "--accel", "bvh", "--gpu-bvh", bvh});
      EXPECT_EQ(refused.code, kExitBadInput) << renderer << " " << bvh;
      const std::string rendererName(nameOf(parseOk({renderer}).renderer));
      EXPECT_NE(refused.error.find("--gpu-bvh: renderer " + rendererName +
                                   " does not take --gpu-bvh; --gpu-bvh applies to --gpu"),
                std::string::npos)
          << refused.error;
    }
  }
}

// The retired variants' flags (schema retired_gpu_variants) are refused
// with every value, the one that remains too, and the error says where the
// measurements went; --help no longer lists them.
TEST(Cli, RetiredGpuVariantsAreRefusedWithTheirRecord) {
  ASSERT_FALSE(schema::kRetiredGpuVariants.empty());
  const std::string help = std::get<CliExit>(parse({"--help"})).output;
  for (const auto& variant : schema::kRetiredGpuVariants) {
    const std::string flag(variant.flag);
    for (const std::string& value : {std::string(variant.name), std::string(variant.kept)}) {
      for (const char* renderer : {"--gpu", "--simd"}) {
        const CliExit refused = test::parseFails({renderer, flag.c_str(), value.c_str()});
        EXPECT_EQ(refused.code, kExitBadInput) << flag << " " << value;
        EXPECT_NE(refused.error.find(flag + ": " + flag + " was retired: the GPU renderer always runs " +
                                     std::string(variant.kept) + " now"),
                  std::string::npos)
            << refused.error;
        EXPECT_NE(refused.error.find(std::string(variant.name) + " are in " + std::string(variant.record)),
                  std::string::npos)
            << refused.error;
      }
    }
    EXPECT_EQ(help.find(flag), std::string::npos) << flag << " is retired, yet --help lists it";
  }
}

TEST(Cli, GpuBvhNeedsABvh) {
  for (const char* bvh : {"binary", "wide"}) {
    const CliExit refused = test::parseFails({"--gpu", "--gpu-bvh", bvh});
    EXPECT_EQ(refused.code, kExitBadInput) << bvh;
    EXPECT_NE(
        refused.error.find("--gpu-bvh: --gpu-bvh " + std::string(bvh) + " needs --accel bvh or auto (accel is none)"),
        std::string::npos)
        << refused.error;
    EXPECT_EQ(exitCode({"--gpu", "--accel", "none", "--gpu-bvh", bvh}), kExitBadInput) << bvh;
  }
  EXPECT_EQ(exitCode({"--gpu", "--accel", "bvh", "--gpu-bvh", "quad"}), kExitBadInput);
  EXPECT_EQ(exitCode({"--gpu", "--accel", "bvh", "--gpu-bvh"}), kExitBadInput) << "a value is needed";
}

TEST(Cli, SaveFrameAndOutputs) {
  const RunConfig c = parseOk({"--warmup", "2", "--frames", "3", "--save-frame", "4:/tmp/a.png", "--save-frame",
                               "0:/tmp/b.png", "--csv", "/tmp/run.csv"});
  ASSERT_EQ(c.saveFrames.size(), 2u);
  EXPECT_EQ(c.saveFrames[0].frame, 4);
  EXPECT_EQ(c.saveFrames[1].file, "/tmp/b.png");
  EXPECT_EQ(metadataPathFor(c), std::filesystem::path("/tmp/run.meta.json"));
}

TEST(Cli, BadValuesExitWithTwo) {
  EXPECT_EQ(exitCode({"--width", "0"}), kExitBadInput);
  EXPECT_EQ(exitCode({"--frames", "many"}), kExitBadInput);
  EXPECT_EQ(exitCode({"--algorithm", "three-pass"}), kExitBadInput);
  EXPECT_EQ(exitCode({"--early-exit", "bounce,sphre"}), kExitBadInput);
  EXPECT_EQ(exitCode({"--stage", "fastest"}), kExitBadInput);
  EXPECT_EQ(exitCode({"--stage", "original", "--algorithm", "single-pass"}), kExitBadInput);
  EXPECT_EQ(exitCode({"--sequential", "--gpu"}), kExitBadInput);
  EXPECT_EQ(exitCode({"--frames", "2", "--warmup", "1", "--save-frame", "3:/tmp/x.png"}), kExitBadInput);
  EXPECT_EQ(exitCode({"--save-frame", "x.png"}), kExitBadInput);
  EXPECT_EQ(exitCode({"--save-frame", "-1:x.png"}), kExitBadInput);
  EXPECT_EQ(exitCode({"--csv", "/nonexistent-dir/run.csv"}), kExitBadInput);
  EXPECT_EQ(exitCode({"--no-such-option"}), kExitBadInput);
}

TEST(Cli, BadValueMessageCarriesUsage) {
  auto result = parse({"--width", "-5"});
  const auto& exit = std::get<CliExit>(result);
  EXPECT_NE(exit.error.find("--width"), std::string::npos) << exit.error;
  EXPECT_NE(exit.error.find("Usage"), std::string::npos) << exit.error;
}

TEST(Cli, HelpAndVersionExitWithZero) {
  auto help = parse({"--help"});
  EXPECT_EQ(std::get<CliExit>(help).code, 0);
  EXPECT_NE(std::get<CliExit>(help).output.find("--early-exit"), std::string::npos);
  for (const char* option : {"--traversal", "packet|single|hybrid", "--hybrid-threshold", "--counters", "--gpu-bvh",
                             "binary|wide|grid", "--gpu-rt-reorder"}) {
    EXPECT_NE(std::get<CliExit>(help).output.find(option), std::string::npos) << option;
  }
  auto version = parse({"--version"});
  EXPECT_EQ(std::get<CliExit>(version).code, 0);
  EXPECT_EQ(std::get<CliExit>(version).output.rfind("raytracer ", 0), 0u);
}

}  // namespace
}  // namespace rt
