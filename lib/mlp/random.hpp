// The one random number generator of lib/mlp: weight initialisation, pattern selection and the per-epoch
// shuffle. Hand-written (not <random>'s distributions, whose output differs between standard libraries)
// so that a seed gives bit-identical networks everywhere, and with a plain 4-word state a checkpoint
// can store.
#pragma once

#include <array>
#include <cstdint>
#include <utility>

namespace contactnn::mlp {

/// xoshiro256** (Blackman & Vigna 2018), seeded through splitmix64.
class Rng {
 public:
  using State = std::array<std::uint64_t, 4>;

  explicit Rng(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (auto& word : state_) word = splitmix64(x);
  }
  /// Restores a state from state(): the sequence continues exactly where it was saved.
  static Rng from_state(const State& state) {
    Rng rng(0);
    rng.state_ = state;
    return rng;
  }
  [[nodiscard]] const State& state() const { return state_; }

  /// An independent seed for one use of a run's seed (stream 0: weights, 1: pattern selection, ...), so
  /// the uses do not share a sequence.
  [[nodiscard]] static std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t stream) {
    std::uint64_t x = seed ^ (0xd1b54a32d192ed03ULL * (stream + 1));
    return splitmix64(x);
  }

  /// Next 64 random bits.
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
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n), n > 0 (Lemire's multiply-shift; the tiny bias for n << 2^64 is irrelevant
  /// here and keeps the draw count fixed, which the checkpoint/resume equality relies on).
  std::uint64_t below(std::uint64_t n) {
    return static_cast<std::uint64_t>((static_cast<unsigned __int128>(next()) * n) >> 64);
  }
  /// Fisher-Yates shuffle of [first, first + n).
  template <class T>
  void shuffle(T* first, std::size_t n) {
    for (std::size_t i = n; i > 1; --i) std::swap(first[i - 1], first[below(i)]);
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  static std::uint64_t splitmix64(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  State state_{};
};

}  // namespace contactnn::mlp
