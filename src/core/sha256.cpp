#include "core/sha256.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

#if defined(__x86_64__)
#include <cpuid.h>
#include <immintrin.h>
#endif

namespace rt {
namespace {

// The standard's constants are the first 32 fractional bits of the square
// roots (initial state) and cube roots (round constants) of the first primes;
// deriving them avoids a hand-typed table. The known-answer tests pin them.
std::array<std::uint32_t, 64> firstPrimes() {
  std::array<std::uint32_t, 64> primes{};
  std::uint32_t candidate = 2;
  for (auto& p : primes) {
    for (;; ++candidate) {
      bool prime = true;
      for (std::uint32_t d = 2; d * d <= candidate; ++d) prime = prime && candidate % d != 0;
      if (prime) break;
    }
    p = candidate++;
  }
  return primes;
}

std::uint32_t fractionBits(long double root) {
  const long double fraction = root - std::floor(root);
  return static_cast<std::uint32_t>(std::ldexp(fraction, 32));
}

struct Constants {
  std::array<std::uint32_t, 8> initialState;
  std::array<std::uint32_t, 64> rounds;
};

const Constants& constants() {
  static const Constants c = [] {
    Constants k{};
    const auto primes = firstPrimes();
    for (std::size_t i = 0; i < 8; ++i)
      k.initialState[i] = fractionBits(std::sqrt(static_cast<long double>(primes[i])));
    for (std::size_t i = 0; i < 64; ++i) k.rounds[i] = fractionBits(std::cbrt(static_cast<long double>(primes[i])));
    return k;
  }();
  return c;
}

std::uint32_t loadBigEndian(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

// FIPS 180-4 section 6.2.2, one 64-byte block at a time.
void compressPortable(std::array<std::uint32_t, 8>& state, const std::uint8_t* block) {
  const auto& k = constants().rounds;
  std::array<std::uint32_t, 64> w{};
  for (int i = 0; i < 16; ++i) w[i] = loadBigEndian(block + 4 * i);
  for (int i = 16; i < 64; ++i) {
    const std::uint32_t s0 = std::rotr(w[i - 15], 7) ^ std::rotr(w[i - 15], 18) ^ (w[i - 15] >> 3);
    const std::uint32_t s1 = std::rotr(w[i - 2], 17) ^ std::rotr(w[i - 2], 19) ^ (w[i - 2] >> 10);
    w[i] = w[i - 16] + s0 + w[i - 7] + s1;
  }
  auto [a, b, c, d, e, f, g, h] = state;
  for (int i = 0; i < 64; ++i) {
    const std::uint32_t sum1 = std::rotr(e, 6) ^ std::rotr(e, 11) ^ std::rotr(e, 25);
    const std::uint32_t choose = (e & f) ^ (~e & g);
    const std::uint32_t t1 = h + sum1 + choose + k[i] + w[i];
    const std::uint32_t sum0 = std::rotr(a, 2) ^ std::rotr(a, 13) ^ std::rotr(a, 22);
    const std::uint32_t majority = (a & b) ^ (a & c) ^ (b & c);
    const std::uint32_t t2 = sum0 + majority;
    h = g;
    g = f;
    f = e;
    e = d + t1;
    d = c;
    c = b;
    b = a;
    a = t1 + t2;
  }
  const std::array<std::uint32_t, 8> add{a, b, c, d, e, f, g, h};
  for (int i = 0; i < 8; ++i) state[i] += add[i];
}

#if defined(__x86_64__)
// The x86 SHA extensions (SHA-NI): sha256rnds2 runs two rounds on the state
// held as the register pair ABEF / CDGH, sha256msg1 and sha256msg2 extend
// the message schedule four words at a time (Intel SDM, "SHA Extensions").
// About ten times the portable loop's speed: a 475 MB scene's hash would
// otherwise outlast its parse.
bool hasShaExtensions() {
  unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
  if (__get_cpuid(1, &eax, &ebx, &ecx, &edx) == 0 || (ecx & bit_SSE4_1) == 0) return false;
  return __get_cpuid_count(7, 0, &eax, &ebx, &ecx, &edx) != 0 && (ebx & bit_SHA) != 0;
}

__attribute__((target("sha,sse4.1"))) void compressShaExtensions(std::array<std::uint32_t, 8>& state,
                                                                 const std::uint8_t* data, std::size_t blocks) {
  const auto& k = constants().rounds;
  // Big-endian words: each 32-bit lane's bytes reversed.
  const __m128i byteSwap = _mm_set_epi64x(0x0c0d0e0f08090a0bLL, 0x0405060700010203LL);
  // state a..h to the pair: abef = (a, b, e, f) and cdgh = (c, d, g, h), high lane first.
  const __m128i dcba = _mm_shuffle_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(&state[0])), 0xB1);
  const __m128i efgh = _mm_shuffle_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(&state[4])), 0x1B);
  __m128i abef = _mm_alignr_epi8(dcba, efgh, 8);
  __m128i cdgh = _mm_blend_epi16(efgh, dcba, 0xF0);
  for (std::size_t block = 0; block < blocks; ++block, data += 64) {
    const __m128i abefIn = abef, cdghIn = cdgh;
    __m128i w[16];  // the message schedule, four words a register
    for (int t = 0; t < 4; ++t) {
      w[t] = _mm_shuffle_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(data + 16 * t)), byteSwap);
    }
    for (int t = 4; t < 16; ++t) {
      const __m128i partial =
          _mm_add_epi32(_mm_sha256msg1_epu32(w[t - 4], w[t - 3]), _mm_alignr_epi8(w[t - 1], w[t - 2], 4));
      w[t] = _mm_sha256msg2_epu32(partial, w[t - 1]);
    }
    for (int t = 0; t < 16; ++t) {
      const __m128i wk = _mm_add_epi32(w[t], _mm_loadu_si128(reinterpret_cast<const __m128i*>(&k[4 * t])));
      cdgh = _mm_sha256rnds2_epu32(cdgh, abef, wk);                           // rounds 4t, 4t+1
      abef = _mm_sha256rnds2_epu32(abef, cdgh, _mm_shuffle_epi32(wk, 0x0E));  // rounds 4t+2, 4t+3
    }
    abef = _mm_add_epi32(abef, abefIn);
    cdgh = _mm_add_epi32(cdgh, cdghIn);
  }
  const __m128i feba = _mm_shuffle_epi32(abef, 0x1B);
  const __m128i hgdc = _mm_shuffle_epi32(cdgh, 0xB1);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(&state[0]), _mm_blend_epi16(feba, hgdc, 0xF0));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(&state[4]), _mm_alignr_epi8(hgdc, feba, 8));
}
#endif

}  // namespace

Sha256::Sha256(Sha256Kernel kernel) : state_(constants().initialState), kernel_(kernel) {}

void Sha256::compressBlocks(const std::uint8_t* data, std::size_t blocks) {
#if defined(__x86_64__)
  static const bool shaExtensions = hasShaExtensions();
  if (shaExtensions && kernel_ == Sha256Kernel::fastest) {
    compressShaExtensions(state_, data, blocks);
    return;
  }
#endif
  for (std::size_t i = 0; i < blocks; ++i) compressPortable(state_, data + 64 * i);
}

void Sha256::update(std::span<const std::uint8_t> bytes) {
  totalBytes_ += bytes.size();
  if (buffered_ > 0) {
    const std::size_t take = std::min(bytes.size(), buffer_.size() - buffered_);
    if (take > 0) std::memcpy(buffer_.data() + buffered_, bytes.data(), take);
    buffered_ += take;
    bytes = bytes.subspan(take);
    if (buffered_ < buffer_.size()) return;
    compressBlocks(buffer_.data(), 1);
    buffered_ = 0;
  }
  const std::size_t whole = bytes.size() / 64;
  compressBlocks(bytes.data(), whole);
  bytes = bytes.subspan(whole * 64);
  if (!bytes.empty()) std::memcpy(buffer_.data(), bytes.data(), bytes.size());
  buffered_ = bytes.size();
}

std::array<std::uint8_t, 32> Sha256::finish() {
  const std::uint64_t bitLength = totalBytes_ * 8;
  const std::uint8_t one = 0x80, zero = 0;
  update({&one, 1});
  while (buffered_ != 56) update({&zero, 1});
  std::array<std::uint8_t, 8> length{};
  for (int i = 0; i < 8; ++i) length[i] = static_cast<std::uint8_t>(bitLength >> (56 - 8 * i));
  update(length);
  std::array<std::uint8_t, 32> digest{};
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 4; ++j) digest[4 * i + j] = static_cast<std::uint8_t>(state_[i] >> (24 - 8 * j));
  return digest;
}

std::string sha256Hex(std::span<const std::uint8_t> bytes, Sha256Kernel kernel) {
  Sha256 hash(kernel);
  hash.update(bytes);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  for (std::uint8_t b : hash.finish()) {
    hex += kHex[b >> 4];
    hex += kHex[b & 15];
  }
  return hex;
}

std::string sha256HexOfFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return sha256Hex(bytes);
}

}  // namespace rt
