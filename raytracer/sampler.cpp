#include "raytracer/sampler.h"

namespace fly::raytracer {
namespace {

using DirectionTable = std::array<std::array<uint32_t, 32>, kGroupDimensions>;

// A primitive polynomial x^s + a_1 x^{s−1} + … + a_{s−1} x + 1 over GF(2), with a = (a_1 … a_{s−1}) in
// binary, and the initial odd direction integers m_1 … m_s (Joe & Kuo 2008, file new-joe-kuo-6.21201, d = 2 …
// 4).
struct SobolPolynomial {
  uint32_t degree;
  uint32_t a;
  std::array<uint32_t, 3> m;
};

constexpr DirectionTable sobolDirections() {
  constexpr std::array<SobolPolynomial, kGroupDimensions - 1> kPolynomials{{
      {1, 0, {1, 0, 0}},
      {2, 1, {1, 3, 0}},
      {3, 1, {1, 3, 1}},
  }};
  DirectionTable v{};
  for (uint32_t k = 0; k < 32; ++k) v[0][k] = 1u << (31 - k);  // van der Corput: m_k = 1
  for (uint32_t d = 1; d < kGroupDimensions; ++d) {
    const SobolPolynomial& p = kPolynomials[d - 1];
    for (uint32_t k = 0; k < 32; ++k) {
      if (k < p.degree) {
        v[d][k] = p.m[k] << (31 - k);  // v_k = m_k / 2^k
        continue;
      }
      // The recurrence of Bratley & Fox ("Implementing Sobol's quasirandom sequence generator", ACM TOMS
      // 14(1), 1988) in direction-number form: v_k = a_1 v_{k−1} ⊕ … ⊕ a_{s−1} v_{k−s+1} ⊕ v_{k−s} ⊕ (v_{k−s}
      // / 2^s).
      uint32_t x = v[d][k - p.degree] ^ (v[d][k - p.degree] >> p.degree);
      for (uint32_t j = 1; j < p.degree; ++j) {
        if ((p.a >> (p.degree - 1 - j)) & 1u) x ^= v[d][k - j];
      }
      v[d][k] = x;
    }
  }
  return v;
}

constexpr detail::SobolNibbleTable nibbleTable(const DirectionTable& v) {
  detail::SobolNibbleTable table{};
  for (uint32_t d = 0; d < kGroupDimensions; ++d) {
    for (uint32_t k = 0; k < 8; ++k) {
      for (uint32_t x = 0; x < 16; ++x) {
        for (uint32_t b = 0; b < 4; ++b) {
          if ((x >> b) & 1u) table[d][k][x] ^= detail::reverseBits(v[d][31 - (4 * k + b)]);
        }
      }
    }
  }
  return table;
}

// v[d][k] = v_{k+1} of Sobol' dimension d; dimension 0 is van der Corput's sequence.
constexpr DirectionTable kDirections = sobolDirections();

// Dimension 1 is the Pascal matrix mod 2 (v = 1, 11, 101, 1111, … in binary fractions).
static_assert(kDirections[1][0] == 0x80000000u && kDirections[1][1] == 0xc0000000u &&
              kDirections[1][2] == 0xa0000000u && kDirections[1][3] == 0xf0000000u &&
              kDirections[1][4] == 0x88000000u);

}  // namespace

namespace detail {
constinit const SobolNibbleTable kSobolNibbles = nibbleTable(kDirections);
}  // namespace detail

}  // namespace fly::raytracer
