#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace rt {

// Which block compression runs: the fastest the CPU offers (the x86 SHA
// extensions where present), or the portable one, which the tests check
// against the same known answers.
enum class Sha256Kernel { fastest, portable };

// SHA-256 (FIPS 180-4), used to fingerprint scene files in run metadata.
class Sha256 {
 public:
  explicit Sha256(Sha256Kernel kernel = Sha256Kernel::fastest);
  void update(std::span<const std::uint8_t> bytes);
  std::array<std::uint8_t, 32> finish();

 private:
  void compressBlocks(const std::uint8_t* data, std::size_t blocks);
  std::array<std::uint32_t, 8> state_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t totalBytes_ = 0;
  Sha256Kernel kernel_;
};

std::string sha256Hex(std::span<const std::uint8_t> bytes, Sha256Kernel kernel = Sha256Kernel::fastest);
std::string sha256HexOfFile(const std::filesystem::path& path);

}  // namespace rt
