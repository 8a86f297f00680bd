#include "core/sha256.h"

#include <gtest/gtest.h>

#include <string_view>

namespace rt {
namespace {

std::span<const std::uint8_t> bytesOf(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

// Every known answer is checked with both kernels: the fastest one (the x86
// SHA extensions on a CPU that has them) and the portable one.
class Sha256KnownAnswers : public ::testing::TestWithParam<Sha256Kernel> {
 protected:
  std::string hashOf(std::string_view text) const { return sha256Hex(bytesOf(text), GetParam()); }
};

// Known answers from FIPS 180-4's examples.
TEST_P(Sha256KnownAnswers, EmptyInput) {
  EXPECT_EQ(hashOf(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST_P(Sha256KnownAnswers, ThreeBytes) {
  EXPECT_EQ(hashOf("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST_P(Sha256KnownAnswers, TwoBlockMessage) {
  EXPECT_EQ(hashOf("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST_P(Sha256KnownAnswers, MillionAs) {
  EXPECT_EQ(hashOf(std::string(1'000'000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

// Pieces that start and end inside blocks, one byte, whole blocks: the
// digest is the one of the text in one piece.
TEST_P(Sha256KnownAnswers, PiecesOfAnySizeGiveTheWholeTextsDigest) {
  std::string text;
  for (int i = 0; i < 1000; ++i) text += static_cast<char>('a' + i * 7 % 26);
  Sha256 pieces(GetParam());
  std::size_t at = 0;
  for (const std::size_t size : {1, 63, 65, 128, 3, 0, 200, 64}) {
    pieces.update(bytesOf(std::string_view(text).substr(at, size)));
    at += size;
  }
  pieces.update(bytesOf(std::string_view(text).substr(at)));
  Sha256 whole(GetParam());
  whole.update(bytesOf(text));
  EXPECT_EQ(pieces.finish(), whole.finish());
}

INSTANTIATE_TEST_SUITE_P(Kernels, Sha256KnownAnswers, ::testing::Values(Sha256Kernel::fastest, Sha256Kernel::portable),
                         [](const auto& kernel) {
                           return kernel.param == Sha256Kernel::fastest ? "fastest" : "portable";
                         });

}  // namespace
}  // namespace rt
