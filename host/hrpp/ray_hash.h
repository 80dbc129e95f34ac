// HRPP ray hashes on the CPU: the mirror of shaders/lib/hrpp_hash.glsl, operation for operation,
// so a key computed here equals the kernels' key bit for bit (tests/hrpp_hash_gpu_test.cpp).
// The definitions (special floats, bins, packing) are documented in the GLSL file.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "bvh/aabb.h"
#include "common/name_table.h"
#include "hrpp_types.h"

namespace hrpp {

static_assert(sizeof(gpu::HashParams) == 64);
static_assert(offsetof(gpu::HashParams, grid_scale) == 16 &&
              offsetof(gpu::HashParams, far_lo) == 32 && offsetof(gpu::HashParams, reach) == 44 &&
              offsetof(gpu::HashParams, second_bits) == 60);

enum class HashKind : std::uint32_t {
  kIeee = HRPP_HASH_IEEE,
  kGridSpherical = HRPP_HASH_GRID_SPHERICAL,
  kTwoPoint = HRPP_HASH_TWO_POINT,
  kLight = HRPP_HASH_LIGHT,
  kLightDepth = HRPP_HASH_LIGHT_DEPTH,
  kMicro21 = HRPP_HASH_MICRO21,
};

// The light-space keys read the ray's end (tmax): meant for shadow rays.
constexpr bool is_light_space(HashKind kind) {
  return kind == HashKind::kLight || kind == HashKind::kLightDepth;
}

struct HashConfig {
  HashKind kind = HashKind::kIeee;
  std::uint32_t bits = 6;  // precision N, 1..8 (the paper's Table 1 uses 6)
  std::uint32_t dir_bits = 0;  // grid-spherical: the direction bins' precision D (0: N);
                               // micro21: 0 or its 3 sphere bits

  friend bool operator==(const HashConfig&, const HashConfig&) = default;
};

// The hash kinds' names (--hrpp-config's hash key); parse_hash_kind throws hrpp::Error otherwise.
inline constexpr NameTable<HashKind, HRPP_HASH_KIND_COUNT> kHashKindNames = {
    {{HashKind::kIeee, "hrpp"},  // the paper's IEEE-754 bits
     {HashKind::kGridSpherical, "grid-spherical"},
     {HashKind::kTwoPoint, "two-point"},
     {HashKind::kLight, "light"},
     {HashKind::kLightDepth, "light-depth"},
     {HashKind::kMicro21, "micro21"}}};
constexpr const char* hash_kind_name(HashKind kind) { return name_in(kHashKindNames, kind); }
inline HashKind parse_hash_kind(std::string_view name) {
  return parse_in(kHashKindNames, name, "hash: unknown hash");
}

// The parameters the kernels get: grid origin and scales over `scene_box`. Throws hrpp::Error
// when bits is outside 1..8, or dir_bits outside 0..8 or set for a key without direction bins.
gpu::HashParams make_hash_params(const HashConfig& config, const Aabb& scene_box);

// The paper's per-float hash at precision n (sign | top n exponent bits | top min(n, 7)
// mantissa bits), on the canonical bits (-0 → +0, NaN → 0x7FC00000).
std::uint32_t float_hash(float f, std::uint32_t n);

// The key of a ray (< 2^48); only the light-space keys read tmax (the ray's end).
std::uint64_t hash_ray(const glm::vec3& origin, const glm::vec3& dir, float tmax,
                       const gpu::HashParams& params);

}  // namespace hrpp
