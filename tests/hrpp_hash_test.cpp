// host/hrpp/ray_hash: the C++ hashes on their edges: keys fit 48 bits, the paper's bit layout and
// swizzle, sign handling (-0 = +0, negative ≠ positive), special floats (NaNs equal, ≠ Inf,
// subnormals keep their top mantissa bits), and monotone precision (rays with equal keys at
// precision N+1 have equal keys at N, for every hash kind); the light-space keys' layout (light
// end on the coarse grid, octahedral cells of comparable solid angle, the receiver's cell).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.h"
#include "hrpp/ray_hash.h"
#include "micro21_bins.h"

namespace hrpp {
namespace {

const Aabb kBox{{-1.25f, -0.5f, -2.0f}, {2.75f, 3.0f, 1.0f}};
constexpr HashKind kKinds[] = {HashKind::kIeee,  HashKind::kGridSpherical, HashKind::kTwoPoint,
                               HashKind::kLight, HashKind::kLightDepth,    HashKind::kMicro21};
// The light-space keys' light-end grid precision at precision n.
std::uint32_t light_bits(std::uint32_t n) { return std::min(n + 1, 8u); }

float f(std::uint32_t bits) { return std::bit_cast<float>(bits); }

std::uint64_t key(HashKind kind, std::uint32_t bits, glm::vec3 o, glm::vec3 d, float tmax = 1.0f) {
  return hash_ray(o, d, tmax, make_hash_params({kind, bits}, kBox));
}

const std::vector<float>& extremes() {
  static const std::vector<float> v = {
      0.0f, -0.0f, f(1), f(0x80000001u), f(0x00400000u), f(0x007FFFFFu), f(0x00800000u),
      1.0f, -1.0f, 0.5f, -3.0f, 1e-30f, f(0x21800000u), f(0x217FFFFFu),
      std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
      std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
      f(0x7FC00000u), f(0xFFC00000u), f(0x7F800001u), f(0x7FFFFFFFu), 2.75f, -1.25f, 3.0f};
  return v;
}

TEST(RayHash, KeysFit48BitsForEveryKindAndPrecision) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::uint32_t> any_bits;
  const auto& ex = extremes();
  std::uniform_int_distribution<std::size_t> pick(0, ex.size() - 1);
  for (HashKind kind : kKinds)
    for (std::uint32_t n = 1; n <= 8; ++n) {
      std::uint64_t all = 0;
      for (int i = 0; i < 2000; ++i) {
        const glm::vec3 o{f(any_bits(rng)), ex[pick(rng)], f(any_bits(rng))};
        const glm::vec3 d{ex[pick(rng)], f(any_bits(rng)), ex[pick(rng)]};
        const std::uint64_t k = key(kind, n, o, d, i % 2 ? ex[pick(rng)] : f(any_bits(rng)));
        EXPECT_LT(k, std::uint64_t{1} << 48) << hash_kind_name(kind) << " N=" << n;
        all |= k;
      }
      // The fields the kinds use: IEEE 3 × 16-bit fields of 2N+1 bits (16 at N = 8), grid 5N,
      // two-point 6N, light 3C + 2N, light-depth 3C + 2N + 8 (C = min(N + 1, 8)), micro21
      // max(3N, 7): random bits must reach the top of the layout.
      const int top = kind == HashKind::kIeee ? 32 + static_cast<int>(n + std::min(n, 7u))
                      : kind == HashKind::kGridSpherical ? static_cast<int>(5 * n) - 1
                      : kind == HashKind::kMicro21 ? std::max(static_cast<int>(3 * n), 7) - 1
                      : kind == HashKind::kTwoPoint      ? static_cast<int>(6 * n) - 1
                      : kind == HashKind::kLight
                          ? static_cast<int>(3 * light_bits(n) + 2 * n) - 1
                          : static_cast<int>(3 * light_bits(n) + 2 * n + 8) - 1;
      EXPECT_NE(all >> top, 0u) << hash_kind_name(kind) << " N=" << n;
      EXPECT_EQ(all >> (top + 1), 0u) << hash_kind_name(kind) << " N=" << n;
    }
}

TEST(RayHash, FloatHashIsSignExponentMantissa) {
  // 1.0 = 0x3F800000: sign 0, exponent 0111'1111, mantissa 0.
  EXPECT_EQ(float_hash(1.0f, 2), 0b0'01'00u);
  EXPECT_EQ(float_hash(-1.0f, 2), 0b1'01'00u);
  // 3.0 = 0x40400000: exponent 1000'0000, mantissa 100...
  EXPECT_EQ(float_hash(3.0f, 3), 0b0'100'100u);
  EXPECT_EQ(float_hash(-3.0f, 8), (1u << 15) | (0x80u << 7) | 0x40u);
  // 16 bits at N = 8: 1 + 8 exponent + 7 mantissa bits.
  EXPECT_EQ(float_hash(-std::numeric_limits<float>::max(), 8), 0xFFFFu - (1u << 7));
  for (std::uint32_t n = 1; n <= 8; ++n) EXPECT_LT(float_hash(f(0xFFFFFFFFu), n), 1u << 16);
}

TEST(RayHash, IeeeKeyIsTheSwizzle) {
  const glm::vec3 o{1.0f, -3.0f, 0.5f}, d{-1.0f, 3.0f, 0.25f};
  for (std::uint32_t n = 1; n <= 8; ++n) {
    const std::uint64_t h0 = float_hash(o.x, n) ^ float_hash(d.z, n);
    const std::uint64_t h1 = float_hash(o.y, n) ^ float_hash(d.y, n);
    const std::uint64_t h2 = float_hash(o.z, n) ^ float_hash(d.x, n);
    EXPECT_EQ(key(HashKind::kIeee, n, o, d), h0 | (h1 << 16) | (h2 << 32));
  }
}

TEST(RayHash, SignsAndSpecialFloats) {
  for (std::uint32_t n = 1; n <= 8; ++n) {
    EXPECT_EQ(float_hash(-0.0f, n), float_hash(0.0f, n));
    EXPECT_NE(float_hash(-2.0f, n), float_hash(2.0f, n));
    const std::uint32_t nan = float_hash(f(0x7FC00000u), n);
    for (std::uint32_t b : {0xFFC00000u, 0x7F800001u, 0xFFFFFFFFu, 0x7FBFFFFFu})
      EXPECT_EQ(float_hash(f(b), n), nan);
    EXPECT_NE(nan, float_hash(std::numeric_limits<float>::infinity(), n));
    EXPECT_NE(float_hash(-std::numeric_limits<float>::infinity(), n),
              float_hash(std::numeric_limits<float>::infinity(), n));
    // Subnormals: exponent 0, the mantissa's top bits kept.
    EXPECT_EQ(float_hash(f(0x00400000u), n), 1u << (std::min(n, 7u) - 1));
    EXPECT_EQ(float_hash(f(1), n), 0u);
  }
  for (HashKind kind : kKinds)
    for (std::uint32_t n = 1; n <= 8; ++n) {
      const glm::vec3 o{0.5f, 1.0f, -0.75f};
      EXPECT_EQ(key(kind, n, {0.0f, 1.0f, -0.75f}, {-0.0f, 0.0f, 1.0f}),
                key(kind, n, {-0.0f, 1.0f, -0.75f}, {0.0f, -0.0f, 1.0f}));
      EXPECT_EQ(key(kind, n, o, {f(0x7FC00000u), 1.0f, 0.0f}),
                key(kind, n, o, {f(0xFFFFFFFFu), 1.0f, 0.0f}));
      if (kind == HashKind::kIeee || n >= 2) {  // the direction's sign is seen
        EXPECT_NE(key(kind, n, o, {0.0f, 0.0f, 1.0f}), key(kind, n, o, {0.0f, 0.0f, -1.0f}));
      }
    }
}

TEST(RayHash, GridHashesQuantiseTheSceneBox) {
  // The box's low corner is cell 0; its high corner the last cell; outside clamps.
  for (std::uint32_t n = 1; n <= 8; ++n) {
    const std::uint64_t mask = (std::uint64_t{1} << (3 * n)) - 1;
    const std::uint64_t last = mask;  // every axis in cell 2^n - 1
    const glm::vec3 d{0.0f, 0.0f, 1.0f};
    EXPECT_EQ(key(HashKind::kGridSpherical, n, kBox.lo, d) & mask, 0u);
    EXPECT_EQ(key(HashKind::kGridSpherical, n, kBox.hi, d) & mask, last);
    EXPECT_EQ(key(HashKind::kGridSpherical, n, kBox.hi + 5.0f, d) & mask, last);
    EXPECT_EQ(key(HashKind::kGridSpherical, n, kBox.lo - 5.0f, d) & mask, 0u);
    // θ: +z is the last θ bin, -z the first; φ of +x is bin 0.
    const std::uint64_t theta_plus = (key(HashKind::kGridSpherical, n, kBox.lo, d) >> (3 * n)) &
                                     ((1u << n) - 1);
    EXPECT_EQ(theta_plus, (1u << n) - 1);
    EXPECT_EQ(key(HashKind::kGridSpherical, n, kBox.lo, -d) >> (3 * n), 0u);
    EXPECT_EQ(key(HashKind::kGridSpherical, n, kBox.lo, {1.0f, 0.0f, 0.0f}) >> (4 * n), 0u);
  }
  EXPECT_THROW(make_hash_params({HashKind::kIeee, 0}, kBox), Error);
  EXPECT_THROW(make_hash_params({HashKind::kIeee, 9}, kBox), Error);
  EXPECT_THROW(parse_hash_kind("md5"), Error);
}

// --hash-dir-bits: grid-spherical's direction bins at their own precision D, the origin cell
// at N as before; D = N is the default key; other keys have no direction bins to set.
TEST(RayHash, GridSphericalDirectionBinsTakeTheirOwnPrecision) {
  const auto with_d = [](std::uint32_t n, std::uint32_t d, glm::vec3 o, glm::vec3 dir) {
    return hash_ray(o, dir, 1.0f, make_hash_params({HashKind::kGridSpherical, n, d}, kBox));
  };
  const glm::vec3 o{0.3f, 1.1f, -0.7f};
  for (std::uint32_t n = 1; n <= 8; ++n)
    for (std::uint32_t d = 1; d <= 8; ++d)
      for (const glm::vec3& dir : {glm::vec3{0.0f, 0.0f, 1.0f}, glm::vec3{0.6f, -0.48f, 0.64f},
                                   glm::vec3{-0.2f, 0.9f, -0.1f}}) {
        const std::uint64_t k = with_d(n, d, o, dir);
        const std::uint64_t origin_mask = (std::uint64_t{1} << (3 * n)) - 1;
        EXPECT_EQ(k & origin_mask, key(HashKind::kGridSpherical, n, o, dir) & origin_mask);
        EXPECT_LT(k >> (3 * n), std::uint64_t{1} << (2 * d)) << n << " " << d;
        // The bins at D are those at N = D, moved above the origin cell.
        EXPECT_EQ(k >> (3 * n), key(HashKind::kGridSpherical, d, o, dir) >> (3 * d));
      }
  EXPECT_EQ(with_d(5, 5, o, {0.6f, -0.48f, 0.64f}), with_d(5, 0, o, {0.6f, -0.48f, 0.64f}));
  EXPECT_THROW(make_hash_params({HashKind::kGridSpherical, 6, 9}, kBox), Error);
  EXPECT_THROW(make_hash_params({HashKind::kIeee, 6, 3}, kBox), Error);
  EXPECT_THROW(make_hash_params({HashKind::kLightDepth, 6, 3}, kBox), Error);
}

// Light-space keys: the light end's coarse cell, the octahedral cell of the direction from the
// light, the receiver's distance from the light (light-depth).
TEST(RayHash, LightKeysAreLightEndDirectionAndReceiver) {
  const glm::vec3 light{0.53f, 2.47f, -0.61f};                       // off every cell boundary
  const glm::vec3 w = glm::normalize(glm::vec3{0.3f, -1.0f, 0.2f});  // light → receivers
  for (std::uint32_t n = 1; n <= 8; ++n) {
    // Receivers on one line from a light point share the light key; light-depth tells apart
    // receivers at different distances (0.2 and 2.5: 3.6 octaves apart), not ones at nearly the
    // same (2.5 and 2.51).
    const glm::vec3 near = light + 0.2f * w, far = light + 2.5f * w;
    EXPECT_EQ(key(HashKind::kLight, n, near, -w, 0.2f), key(HashKind::kLight, n, far, -w, 2.5f));
    EXPECT_NE(key(HashKind::kLightDepth, n, near, -w, 0.2f),
              key(HashKind::kLightDepth, n, far, -w, 2.5f));
    EXPECT_EQ(key(HashKind::kLightDepth, n, far, -w, 2.5f),
              key(HashKind::kLightDepth, n, light + 2.51f * w, -w, 2.51f));
    // Another light: another key. The end is the light cell: a ray ending at the box's high
    // corner is in the last coarse cell, one ending at its low corner in cell 0.
    const std::uint64_t cell = (std::uint64_t{1} << (3 * light_bits(n))) - 1;
    EXPECT_EQ(key(HashKind::kLight, n, kBox.lo + 1.0f, {-1.0f, -1.0f, -1.0f}, 1.0f) & cell, 0u);
    EXPECT_EQ(key(HashKind::kLight, n, kBox.hi - 1.0f, {1.0f, 1.0f, 1.0f}, 1.0f) & cell, cell);
    // Octahedral cells of the direction from the light (-d): +z is the diamond's centre, -z
    // its corner cells.
    const std::uint32_t half = 1u << (n - 1), last = (1u << n) - 1;
    const auto octa = [&](glm::vec3 d) {
      return key(HashKind::kLight, n, {0.0f, 0.0f, 0.0f}, d, 1.0f) >> (3 * light_bits(n));
    };
    EXPECT_EQ(octa({0.0f, 0.0f, -1.0f}), half | (std::uint64_t{half} << n));
    EXPECT_EQ(octa({0.0f, 0.0f, 1.0f}), last | (std::uint64_t{last} << n));
    EXPECT_EQ(octa({1.0f, 0.0f, 0.0f}), 0u | (std::uint64_t{half} << n));  // -x: a = -1
  }
  // Cells of comparable solid angle: uniform directions fill every cell at N = 3, the largest
  // cell's share at most 3.5 times the smallest's (measured: 3.0).
  std::mt19937 rng(5);
  std::normal_distribution<float> g(0.0f, 1.0f);
  std::map<std::uint64_t, int> count;
  for (int i = 0; i < 64000; ++i)
    ++count[key(HashKind::kLight, 3, {0.0f, 0.0f, 0.0f}, {g(rng), g(rng), g(rng)}, 1.0f) >>
            (3 * light_bits(3))];
  EXPECT_EQ(count.size(), 64u);
  int lo = 1 << 30, hi = 0;
  for (const auto& [cell, c] : count) lo = std::min(lo, c), hi = std::max(hi, c);
  EXPECT_LT(2 * hi, 7 * lo);
}

// Rays with equal keys at precision N+1 have equal keys at N: a finer hash only splits entries
// (hrpp's own kinds; MICRO'21's xor of the direction bins into the cell is not monotone).
TEST(RayHash, PrecisionIsMonotone) {
  std::mt19937 rng(11);
  std::normal_distribution<float> jitter(0.0f, 1.0f);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<std::pair<glm::vec3, glm::vec3>> rays;
  for (int c = 0; c < 64; ++c) {  // clusters of similar rays so keys collide
    const glm::vec3 o{u(rng) * 2.0f, u(rng) * 2.0f, u(rng) * 2.0f};
    const glm::vec3 d = glm::normalize(glm::vec3{u(rng), u(rng), u(rng)});
    const float spread = std::ldexp(1.0f, -(c % 12));
    for (int i = 0; i < 64; ++i)
      rays.emplace_back(o + spread * glm::vec3{jitter(rng), jitter(rng), jitter(rng)},
                        d + spread * glm::vec3{jitter(rng), jitter(rng), jitter(rng)});
  }
  for (HashKind kind : kKinds) {
    if (kind == HashKind::kMicro21) continue;  // its direction bins xor into the cell's bits
    std::size_t merged = 0;  // fine keys that share a coarse key, over every precision
    for (std::uint32_t n = 1; n < 8; ++n) {
      std::map<std::uint64_t, std::uint64_t> coarse_of_fine;
      std::set<std::uint64_t> coarse_keys;
      int collisions = 0;
      for (const auto& [o, d] : rays) {
        const std::uint64_t fine = key(kind, n + 1, o, d), coarse = key(kind, n, o, d);
        const auto [it, inserted] = coarse_of_fine.emplace(fine, coarse);
        if (!inserted) {
          ++collisions;
          EXPECT_EQ(it->second, coarse) << hash_kind_name(kind) << " N=" << n;
        }
      }
      EXPECT_GT(collisions, 0) << hash_kind_name(kind) << " N=" << n;
      for (const auto& [fine, coarse] : coarse_of_fine) coarse_keys.insert(coarse);
      merged += coarse_of_fine.size() - coarse_keys.size();
    }
    // Lowering the precision must merge keys somewhere, or N would not change the hash.
    EXPECT_GT(merged, 0u) << hash_kind_name(kind);
  }
}

// MICRO'21's hash as its simulator's rt-sim.cc computes it (hash_origin_grid, hash_direction_
// spherical, hash_grid_spherical), in double with acos and atan2: the origin's cell packed
// x << 2n | y << n | z, xor (φ° >> 5) << 3 | (θ° >> 5), θ° = acos(d.z) and φ° = atan2(d.y, d.x)
// + π in whole degrees. Sets `near_edge` when the ray lies within `margin` of a cell or bin edge,
// where float rounding may move it by one bin (micro21_bins.h).
std::uint64_t micro21_source_key(glm::vec3 o, glm::vec3 d, const Aabb& box, std::uint32_t n,
                                 bool& near_edge, double margin = 1e-4) {
  const double cells = std::ldexp(1.0, static_cast<int>(n));
  std::uint64_t cell[3];
  near_edge = false;
  for (int a = 0; a < 3; ++a) {
    const double x = (static_cast<double>(o[a]) - box.lo[a]) / (box.hi[a] - box.lo[a]) * cells;
    near_edge |= std::fabs(x - std::round(x)) < margin;
    cell[a] = static_cast<std::uint64_t>(std::clamp(x, 0.0, cells - 1.0));
  }
  const glm::dvec3 u = glm::normalize(glm::dvec3(d));
  const double theta = std::acos(std::clamp(u.z, -1.0, 1.0)) / std::acos(-1.0) * 180.0;
  const double phi = (std::atan2(u.y, u.x) + std::acos(-1.0)) / std::acos(-1.0) * 180.0;
  near_edge |= std::fabs(theta / 32.0 - std::round(theta / 32.0)) < margin ||
               std::fabs(phi / 32.0 - std::round(phi / 32.0)) < margin;
  const std::uint64_t dir = ((static_cast<std::uint64_t>(phi) >> 5) << 3) |
                            (static_cast<std::uint64_t>(theta) >> 5);
  return ((cell[0] << (2 * n)) | (cell[1] << n) | cell[2]) ^ dir;
}

// Hand-worked rays on a 32-unit cube at MICRO'21's 5 grid bits: cell (5, 17, 30) is 5 << 10 |
// 17 << 5 | 30 = 5694; +z is θ 0°, φ 180° (atan2(0, 0) = 0): bins (0, 5), 5694 ^ 40 = 5654;
// (1, 1, 0)/√2 is θ 90°, φ 225°: bins (2, 7), 5694 ^ 58 = 5636; -x is φ 360° (atan2(+0, -1) =
// π): bins (2, 11), 5694 ^ 90 = 5732; -z from the centre: bins (5, 5), 16912 ^ 45 = 16957; and
// (0.36, -0.48, -0.8) from cell 0: θ 143°, φ 126°: bins (4, 3), 0 ^ 28 = 28.
TEST(RayHash, Micro21KeysAreTheSimulatorsOnHandWorkedRays) {
  const Aabb cube{glm::vec3(0.0f), glm::vec3(32.0f)};
  const auto k = [&](glm::vec3 o, glm::vec3 d) {
    return hash_ray(o, d, 1.0f, make_hash_params({HashKind::kMicro21, 5}, cube));
  };
  const glm::vec3 o{5.5f, 17.2f, 30.9f};
  const float s = std::sqrt(0.5f);
  EXPECT_EQ(k(o, {0.0f, 0.0f, 1.0f}), 5654u);
  EXPECT_EQ(k(o, {s, s, 0.0f}), 5636u);
  EXPECT_EQ(k(o, {-1.0f, 0.0f, 0.0f}), 5732u);
  EXPECT_EQ(k(o, {-1.0f, -0.0f, 0.0f}), 5732u);  // -0 is +0: atan2(+0, -1)
  EXPECT_EQ(k({16.0f, 16.0f, 16.0f}, {0.0f, 0.0f, -1.0f}), 16957u);
  EXPECT_EQ(k({0.5f, 0.5f, 0.5f}, {0.36f, -0.48f, -0.8f}), 28u);
  EXPECT_EQ(k({31.9f, 0.1f, 12.3f}, {-0.6f, 0.0f, 0.8f}), 31829u);
  // The direction's length does not matter (the source's directions are unit length).
  EXPECT_EQ(k({0.5f, 0.5f, 0.5f}, {3.6f, -4.8f, -8.0f}), 28u);
  // The zero direction as the source's: θ = acos 0 = 90°, φ = 180°: bins (2, 5).
  EXPECT_EQ(k(o, {0.0f, 0.0f, 0.0f}), 5694u ^ ((5u << 3) | 2u));
  EXPECT_NO_THROW(make_hash_params({HashKind::kMicro21, 5, 3}, cube));
  EXPECT_THROW(make_hash_params({HashKind::kMicro21, 5, 4}, cube), Error);
}

// The same on random rays in a scene box, at every grid precision: equal to the source's key
// except within a rounding of an edge (skipped: fewer than 1 in 500).
TEST(RayHash, Micro21KeysAreTheSimulatorsOnRandomRays) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> t(-0.1f, 1.1f), dir(-1.0f, 1.0f);
  const glm::vec3 e = kBox.extent();
  for (std::uint32_t n = 1; n <= 8; ++n) {
    const gpu::HashParams params = make_hash_params({HashKind::kMicro21, n}, kBox);
    int compared = 0, skipped = 0;
    for (int i = 0; i < 20000; ++i) {
      const glm::vec3 o = kBox.lo + glm::vec3(t(rng), t(rng), t(rng)) * e;
      const glm::vec3 d{dir(rng), dir(rng), dir(rng)};
      if (glm::length(d) < 1e-3f) continue;
      bool near_edge = false;
      const std::uint64_t expected = micro21_source_key(o, d, kBox, n, near_edge);
      if (near_edge) {
        ++skipped;
        continue;
      }
      ++compared;
      ASSERT_EQ(hash_ray(o, d, 1.0f, params), expected) << "N=" << n << " ray " << i;
    }
    EXPECT_LT(skipped * 500, compared) << "N=" << n;
  }
}

// The bin edges of micro21_bins.h are cos 32k° |cos 32k°| and the diamond angle of 32k°,
// rounded to float.
TEST(RayHash, Micro21BinEdgesAreThe32DegreeEdges) {
  const double pi = std::acos(-1.0);
  for (int k = 0; k <= 6; ++k) {  // θ: the bin of an angle 1e-3° past each edge is k
    const double a = (32.0 * k + 1e-3) * pi / 180.0;
    if (a > pi) break;
    const double c = std::cos(a) * std::fabs(std::cos(a));
    EXPECT_EQ(gpu::hrpp_micro21_theta_bin(static_cast<float>(c)), static_cast<std::uint32_t>(k))
        << k;
    const double before = (32.0 * k - 1e-3) * pi / 180.0;
    if (k > 0) {
      const double cb = std::cos(before) * std::fabs(std::cos(before));
      EXPECT_EQ(gpu::hrpp_micro21_theta_bin(static_cast<float>(cb)),
                static_cast<std::uint32_t>(k - 1))
          << k;
    }
  }
  const auto diamond = [](double a) {
    const double x = std::cos(a), y = std::sin(a), s = std::fabs(x) + std::fabs(y);
    const double u = x / s, v = y / s;
    return v >= 0.0 ? (u >= 0.0 ? v : 1.0 - u) : (u < 0.0 ? 2.0 - v : 3.0 + u);
  };
  for (int k = 0; k <= 11; ++k) {  // φ
    const double after = (32.0 * k + 1e-3) * pi / 180.0;
    EXPECT_EQ(gpu::hrpp_micro21_phi_bin(static_cast<float>(diamond(after))),
              static_cast<std::uint32_t>(k))
        << k;
    if (k > 0) {
      const double before = (32.0 * k - 1e-3) * pi / 180.0;
      EXPECT_EQ(gpu::hrpp_micro21_phi_bin(static_cast<float>(diamond(before))),
                static_cast<std::uint32_t>(k - 1))
          << k;
    }
  }
}

}  // namespace
}  // namespace hrpp
