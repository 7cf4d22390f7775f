// The standard normals imuconv montecarlo draws its noise from: xoshiro256++ for the bits and
// the ziggurat method for the normals, both written here from their published definitions so
// that a seed gives the same numbers with any compiler and standard library (the library's
// normal_distribution is implementation-defined).
//
//   xoshiro256++ (D. Blackman, S. Vigna, "Scrambled linear pseudorandom number generators",
//   ACM TOMS 47(4), 2021): 256 bits of state, output rotl(s0 + s3, 23) + s0; the state is
//   filled from a 64-bit seed by SplitMix64, as its authors recommend.
//
//   The ziggurat (G. Marsaglia, W. W. Tsang, "The Ziggurat Method for Generating Random
//   Variables", J. Stat. Softw. 5(8), 2000), 256 layers over f(x) = exp(-x^2/2), x >= 0.
//   Layer i >= 1 is the rectangle [0, x_i] x [f(x_i), f(x_{i+1})], the base layer 0 the
//   rectangle [0, r] x [0, f(r)] plus the tail beyond r; all have the same area v, so
//   x_1 = r, f(x_{i+1}) = f(x_i) + v / x_i, x_256 = 0, and the base's pseudo-width
//   x_0 = v / f(r). A draw picks a layer i and a point x = u x_i (u uniform in [0, 1)):
//   x < x_{i+1} lies under f whatever its height (98.5 % of draws: one 64-bit word, a
//   multiply and a compare); otherwise the base draws from the tail (Marsaglia, 1964) and
//   the other layers test a uniform height against f(x). Each of these exits is exact
//   rejection sampling, so the result is N(0, 1) up to the tables' rounding (relative
//   1e-15 in the layers' areas). A random sign makes it symmetric.
//   r = 3.6541528853610088 is the 256-layer value (the top layer then closes at x_256 = 0
//   to 1e-13 of v, checked by tests/montecarlo/normal.cpp); v follows from r:
//   v = r f(r) + int_r^inf f = r f(r) + sqrt(pi/2) erfc(r / sqrt 2).
//
// What it costs per normal: almost always one xoshiro step and no libm call. Only the table
// set-up (once), the tail and the wedges (1.5 % of draws) call exp, log and erfc; the
// numbers therefore depend on the C library only there (the Box-Muller draws used before
// called log, sin and cos for every pair).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace imuconv::montecarlo {

/// SplitMix64's finaliser of x + golden gamma: one step of SplitMix64 from state x.
constexpr std::uint64_t SplitMix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

class Xoshiro256pp {
 public:
  /// The state from SplitMix64 started at `seed` (its first four outputs).
  explicit Xoshiro256pp(std::uint64_t seed) {
    for (auto& w : s_) {
      w = SplitMix64(seed);
      seed += 0x9e3779b97f4a7c15ULL;
    }
  }
  /// A given state (not all zero), for the reference sequence test.
  explicit Xoshiro256pp(const std::array<std::uint64_t, 4>& state) : s_(state) {}

  std::uint64_t operator()() {
    const std::uint64_t out = Rotl(s_[0] + s_[3], 23) + s_[0];
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = Rotl(s_[3], 45);
    return out;
  }

 private:
  static constexpr std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::array<std::uint64_t, 4> s_;
};

/// The ziggurat's tables (see the file comment), built once.
struct ZigguratTables {
  static constexpr int kLayers = 256;
  static constexpr double kR = 3.6541528853610088;
  double v = 0.0;
  std::array<double, kLayers + 1> x{};  ///< x_0 (pseudo-width of the base), x_1 = r, ..., x_256 = 0
  std::array<double, kLayers + 1>
      f{};  ///< f(x_i); f_0 = f(r) (the base's rectangle top), f_256 = 1

  ZigguratTables() {
    const double fr = std::exp(-0.5 * kR * kR);
    v = kR * fr + std::sqrt(0.5 * M_PI) * std::erfc(kR / std::sqrt(2.0));
    x[0] = v / fr;
    f[0] = fr;
    x[1] = kR;
    f[1] = fr;
    for (int i = 1; i < kLayers - 1; ++i) {
      f[i + 1] = f[i] + v / x[i];
      x[i + 1] = std::sqrt(-2.0 * std::log(f[i + 1]));
    }
    x[kLayers] = 0.0;
    f[kLayers] = 1.0;
  }
  static const ZigguratTables& Get() {
    static const ZigguratTables t;
    return t;
  }
};

/// Standard normals from one trial's generator.
class Normal {
 public:
  explicit Normal(std::uint64_t seed) : bits_(seed), z_(ZigguratTables::Get()) {}

  /// n normals into out[0..n), in the order n calls would give them: one tight loop keeps
  /// the generator's state in registers (about 3x faster than drawing them one by one
  /// between other work, bench/suite.cpp BM_MonteCarlo).
  void Fill(double* out, std::size_t n) {
    for (std::size_t j = 0; j < n; ++j) out[j] = (*this)();
  }

  double operator()() {
    for (;;) {
      const std::uint64_t b = bits_();
      const int i = static_cast<int>(b & 0xff);  // layer: the low 8 bits
      // Sign from bit 8, as a factor: a branch on it would be mispredicted half the time.
      const double sign = kSign[(b >> 8) & 1];
      const double u = static_cast<double>(b >> 11) * 0x1.0p-53;  // [0, 1): the high 53 bits
      const double x = u * z_.x[i];
      if (x < z_.x[i + 1]) return sign * x;
      if (i == 0) return sign * Tail();
      // The wedge of layer i: a uniform height in [f(x_i), f(x_{i+1})] under f(x)?
      const double y = z_.f[i] + Uniform() * (z_.f[i + 1] - z_.f[i]);
      if (y < std::exp(-0.5 * x * x)) return sign * x;
    }
  }

 private:
  double Uniform() { return static_cast<double>(bits_() >> 11) * 0x1.0p-53; }              // [0, 1)
  double OpenUniform() { return (static_cast<double>(bits_() >> 11) + 1.0) * 0x1.0p-53; }  // (0, 1]
  /// r + the excess over r of a normal beyond r (Marsaglia 1964: e, e' exponential,
  /// e / r accepted when 2 e' > (e / r)^2).
  double Tail() {
    for (;;) {
      const double e = -std::log(OpenUniform()) / ZigguratTables::kR;
      const double e2 = -std::log(OpenUniform());
      if (e2 + e2 > e * e) return ZigguratTables::kR + e;
    }
  }

  static constexpr double kSign[2] = {1.0, -1.0};
  Xoshiro256pp bits_;
  const ZigguratTables& z_;
};

}  // namespace imuconv::montecarlo
