#pragma once
/// @file SyntheticRandom.h
/// @brief Portable random numbers for the synthetic scenes: std::mt19937 is specified bit for bit by the
/// standard, the std:: distributions are not, so values are derived from its raw output here. Per-pixel noise
/// comes from a counter-based hash instead of a sequence, so it does not depend on the order pixels are visited.
#include <cmath>
#include <cstdint>
#include <random>

namespace tissuemosaic::synthetic {

/// Uniform in [0, 1) from one mt19937 draw (24 bits, exact in float and double).
inline double uniform01(std::mt19937& generator) { return (generator() >> 8) * (1.0 / 16777216.0); }
inline double uniform(std::mt19937& generator, double low, double high) {
  return low + (high - low) * uniform01(generator);
}

/// SplitMix64 finaliser: a well-mixed 64-bit hash of a 64-bit counter.
inline uint64_t hash64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// A standard normal value that depends only on (seed, stream, index): Box-Muller on two hashed uniforms.
inline double hashedGaussian(uint32_t seed, uint32_t stream, uint64_t index) {
  const uint64_t h = hash64((static_cast<uint64_t>(seed) << 32 | stream) ^ hash64(index));
  const double u1 = ((h >> 40) + 0.5) * (1.0 / 16777216.0);           // (0, 1)
  const double u2 = ((h >> 16) & 0xFFFFFF) * (1.0 / 16777216.0);      // [0, 1)
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

}  // namespace tissuemosaic::synthetic
