#pragma once
// Deterministic random numbers: the same seed gives the same stream on every platform and
// standard library (std::uniform_real_distribution does not promise that).

#include <cstdint>

namespace kincal {

/// SplitMix64: seeds the generator and derives independent sub-seeds.
inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// Seed of sub-stream `stream` of `seed` (e.g. stream 1 = true parameters, 2 = poses, ...).
inline std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t stream) {
  return splitmix64(splitmix64(seed) ^ splitmix64(stream + 0x632be59bd9b4e019ULL));
}

/// xoshiro256** by Blackman and Vigna: fast, small state, good statistical quality.
class Random {
 public:
  explicit Random(std::uint64_t seed) {
    for (auto& s : state_) s = seed = splitmix64(seed);
  }
  std::uint64_t next() {
    const std::uint64_t result = rotl(state_[1] * 5, 7) * 9;
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = rotl(state_[3], 45);
    return result;
  }
  /// Uniform in [0, 1) with 53 random bits.
  double uniform01() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// Uniform in [-half_width, half_width).
  double symmetric(double half_width) { return half_width * (2.0 * uniform01() - 1.0); }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t state_[4];
};

}  // namespace kincal
