#include "hrpp/ray_hash.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>

#include "common/error.h"
#include "micro21_bins.h"

namespace hrpp {
namespace {

std::uint32_t bits_of(float f) { return std::bit_cast<std::uint32_t>(f); }
float from_bits(std::uint32_t b) { return std::bit_cast<float>(b); }

std::uint32_t canonical_bits(float f) {
  const std::uint32_t b = bits_of(f);
  if ((b & 0x7FFFFFFFu) > 0x7F800000u) return 0x7FC00000u;  // NaN
  if (b == 0x80000000u) return 0u;                           // -0
  return b;
}

std::uint32_t abs_bits(float f) { return bits_of(f) & 0x7FFFFFFFu; }

float flushed(float f) {
  const std::uint32_t b = canonical_bits(f);
  return (b & 0x7F800000u) == 0u ? 0.0f : from_bits(b);
}

glm::vec3 flushed(const glm::vec3& v) { return {flushed(v.x), flushed(v.y), flushed(v.z)}; }

std::uint32_t bin(float x, std::uint32_t cells) {
  if (abs_bits(x) > 0x7F800000u || x < 0.0f) return 0u;
  if (x >= static_cast<float>(cells)) return cells - 1u;
  return std::min(static_cast<std::uint32_t>(x), cells - 1u);
}

std::uint32_t grid_cell(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& scale,
                        std::uint32_t n) {
  const std::uint32_t cells = 1u << n;
  const glm::vec3 x = (p - lo) * scale;
  return bin(x.x, cells) | (bin(x.y, cells) << n) | (bin(x.z, cells) << (2u * n));
}

bool scaled_direction(const glm::vec3& dir, glm::vec3& u) {
  u = glm::vec3(0.0f);
  const glm::vec3 d = flushed(dir);
  const std::uint32_t m = std::max({abs_bits(d.x), abs_bits(d.y), abs_bits(d.z)});
  if (m == 0u || m >= 0x7F800000u) return false;
  const std::uint32_t e = m >> 23;
  const glm::vec3 s = d * from_bits((255u - e) << 23);
  constexpr std::uint32_t kTiny = 0x21800000u;  // 2^-60
  u = {abs_bits(s.x) < kTiny ? 0.0f : s.x, abs_bits(s.y) < kTiny ? 0.0f : s.y,
       abs_bits(s.z) < kTiny ? 0.0f : s.z};
  return true;
}

float diamond_angle(float x, float y) {
  const float s = std::fabs(x) + std::fabs(y);
  const float a = x / s;
  const float b = y / s;
  const float q1 = 1.0f - a;
  const float q2 = 2.0f - b;
  const float q3 = 3.0f + a;
  return b >= 0.0f ? (a >= 0.0f ? b : q1) : (a < 0.0f ? q2 : q3);
}

float signed_cos2(const glm::vec3& u) {
  const float len2 = u.x * u.x + u.y * u.y + u.z * u.z;
  return (u.z * std::fabs(u.z)) / len2;
}

std::uint32_t direction_bins(const glm::vec3& dir, std::uint32_t n) {
  const std::uint32_t cells = 1u << n;
  glm::vec3 u;
  if (!scaled_direction(dir, u)) return 0u;
  const float theta_x = (signed_cos2(u) + 1.0f) * from_bits((126u + n) << 23);
  const std::uint32_t theta = bin(theta_x, cells);
  const float p = (u.x != 0.0f || u.y != 0.0f) ? diamond_angle(u.x, u.y) : 0.0f;
  const float phi_x = p * from_bits((125u + n) << 23);
  const std::uint32_t phi = bin(phi_x, cells);
  return theta | (phi << n);
}

std::uint64_t hash_ieee(const glm::vec3& o, const glm::vec3& d, std::uint32_t n) {
  const std::uint32_t h0 = float_hash(o.x, n) ^ float_hash(d.z, n);
  const std::uint32_t h1 = float_hash(o.y, n) ^ float_hash(d.y, n);
  const std::uint32_t h2 = float_hash(o.z, n) ^ float_hash(d.x, n);
  return std::uint64_t{h0} | (std::uint64_t{h1} << 16) | (std::uint64_t{h2} << 32);
}

std::uint64_t hash_grid_spherical(const glm::vec3& o, const glm::vec3& d,
                                  const gpu::HashParams& h) {
  const std::uint32_t n = h.bits;
  return std::uint64_t{grid_cell(flushed(o), h.grid_lo, h.grid_scale, n)} |
         (std::uint64_t{direction_bins(d, h.second_bits)} << (3u * n));
}

std::uint64_t hash_micro21(const glm::vec3& o, const glm::vec3& d, const gpu::HashParams& h) {
  const std::uint32_t n = h.bits, cells = 1u << n;
  const glm::vec3 x = (flushed(o) - h.grid_lo) * h.grid_scale;
  const std::uint32_t cell = (bin(x.x, cells) << (2u * n)) | (bin(x.y, cells) << n) |
                             bin(x.z, cells);
  glm::vec3 u;
  std::uint32_t theta = HRPP_MICRO21_THETA_BIN_ZERO, phi = HRPP_MICRO21_PHI_BIN_VERTICAL;
  if (scaled_direction(d, u)) {
    theta = gpu::hrpp_micro21_theta_bin(signed_cos2(u));
    if (u.y == 0.0f && u.x < 0.0f)
      phi = HRPP_MICRO21_PHI_BIN_MINUS_X;
    else if (u.x != 0.0f || u.y != 0.0f)
      phi = gpu::hrpp_micro21_phi_bin(diamond_angle(-u.x, -u.y));
  }
  return std::uint64_t{cell ^ ((phi << HRPP_MICRO21_SPHERE_BITS) | theta)};
}

std::uint64_t hash_two_point(const glm::vec3& o, const glm::vec3& d, const gpu::HashParams& h) {
  const std::uint32_t n = h.bits;
  const glm::vec3 oc = flushed(o);
  glm::vec3 u;
  std::uint32_t far_cell = 0u;
  if (scaled_direction(d, u)) {
    const float m = from_bits(std::max({abs_bits(u.x), abs_bits(u.y), abs_bits(u.z)}));
    const float k = h.reach / m;
    const glm::vec3 q = oc + u * k;
    far_cell = grid_cell(q, h.far_lo, h.far_scale, n);
  }
  return std::uint64_t{grid_cell(oc, h.grid_lo, h.grid_scale, n)} |
         (std::uint64_t{far_cell} << (3u * n));
}

std::uint32_t octahedral_cell(const glm::vec3& dir, std::uint32_t n) {
  const std::uint32_t cells = 1u << n;
  glm::vec3 u;
  if (!scaled_direction(dir, u)) return 0u;
  const float s = std::fabs(u.x) + std::fabs(u.y) + std::fabs(u.z);
  float a = u.x / s;
  float b = u.y / s;
  if (u.z < 0.0f) {
    const float fa = 1.0f - std::fabs(b);
    const float fb = 1.0f - std::fabs(a);
    a = a >= 0.0f ? fa : -fa;
    b = b >= 0.0f ? fb : -fb;
  }
  const float scale = from_bits((126u + n) << 23);
  const float x = (a + 1.0f) * scale;
  const float y = (b + 1.0f) * scale;
  return bin(x, cells) | (bin(y, cells) << n);
}

std::uint64_t hash_light(const glm::vec3& o, const glm::vec3& d, float tmax,
                         const gpu::HashParams& h, bool with_depth) {
  const std::uint32_t n = h.bits, c = h.second_bits;
  const glm::vec3 oc = flushed(o);
  const glm::vec3 e = oc + flushed(d) * flushed(tmax);
  std::uint64_t key = std::uint64_t{grid_cell(e, h.far_lo, h.far_scale, c)} |
                      (std::uint64_t{octahedral_cell(-d, n)} << (3u * c));
  if (with_depth) key |= std::uint64_t{(canonical_bits(tmax) >> 21) & 0xFFu} << (3u * c + 2u * n);
  return key;
}

// 2^n / extent as a float, 0 for a flat or non-finite extent (one cell along that axis).
glm::vec3 grid_scale(const glm::vec3& extent, std::uint32_t n) {
  glm::vec3 s;
  for (int a = 0; a < 3; ++a)
    s[a] = (extent[a] > 0.0f && std::isfinite(extent[a]))
               ? flushed(static_cast<float>(std::ldexp(1.0, static_cast<int>(n)) /
                                            static_cast<double>(extent[a])))
               : 0.0f;
  return s;
}

}  // namespace

gpu::HashParams make_hash_params(const HashConfig& config, const Aabb& scene_box) {
  if (config.bits < 1 || config.bits > HRPP_HASH_BITS_MAX)
    throw Error("hash_bits: " + std::to_string(config.bits) + " is outside 1..8");
  if (config.dir_bits > HRPP_HASH_BITS_MAX)
    throw Error("hash_dir_bits: " + std::to_string(config.dir_bits) + " is outside 1..8");
  if (config.kind == HashKind::kMicro21 && config.dir_bits > 0 &&
      config.dir_bits != HRPP_MICRO21_SPHERE_BITS)
    throw Error("hash_dir_bits: micro21 has MICRO'21's 3 sphere bits only");
  if (config.dir_bits > 0 && config.kind != HashKind::kGridSpherical &&
      config.kind != HashKind::kMicro21)
    throw Error(std::string("hash_dir_bits: only grid-spherical keys have direction bins, not ") +
                hash_kind_name(config.kind));
  gpu::HashParams p{};
  p.kind = static_cast<std::uint32_t>(config.kind);
  p.bits = config.bits;
  const Aabb box = scene_box.empty() ? Aabb{glm::vec3(0.0f), glm::vec3(0.0f)} : scene_box;
  const glm::vec3 extent = box.extent();
  const float reach = std::max({extent.x, extent.y, extent.z});
  p.grid_lo = flushed(box.lo);
  p.grid_scale = grid_scale(extent, config.bits);
  p.reach = std::isfinite(reach) ? flushed(reach) : 0.0f;
  if (is_light_space(config.kind)) {  // far_* hold the light end's grid over the scene box
    p.second_bits = std::min(config.bits + 1, 8u);
    p.far_lo = p.grid_lo;
    p.far_scale = grid_scale(extent, p.second_bits);
    return p;
  }
  if (config.kind == HashKind::kGridSpherical)
    p.second_bits = config.dir_bits > 0 ? config.dir_bits : config.bits;
  if (config.kind == HashKind::kMicro21) p.second_bits = HRPP_MICRO21_SPHERE_BITS;
  p.far_lo = flushed(box.lo - glm::vec3(p.reach));
  p.far_scale = grid_scale(extent + glm::vec3(2.0f * p.reach), config.bits);
  return p;
}

std::uint32_t float_hash(float f, std::uint32_t n) {
  const std::uint32_t b = canonical_bits(f);
  const std::uint32_t m_bits = std::min(n, 7u);
  const std::uint32_t sign = b >> 31;
  const std::uint32_t exponent = (b >> 23) & 0xFFu;
  const std::uint32_t mantissa = b & 0x7FFFFFu;
  return (sign << (n + m_bits)) | ((exponent >> (8u - n)) << m_bits) | (mantissa >> (23u - m_bits));
}

std::uint64_t hash_ray(const glm::vec3& origin, const glm::vec3& dir, float tmax,
                       const gpu::HashParams& params) {
  switch (params.kind) {
    case HRPP_HASH_GRID_SPHERICAL:
      return hash_grid_spherical(origin, dir, params);
    case HRPP_HASH_TWO_POINT:
      return hash_two_point(origin, dir, params);
    case HRPP_HASH_LIGHT:
      return hash_light(origin, dir, tmax, params, false);
    case HRPP_HASH_LIGHT_DEPTH:
      return hash_light(origin, dir, tmax, params, true);
    case HRPP_HASH_MICRO21:
      return hash_micro21(origin, dir, params);
    default:
      return hash_ieee(origin, dir, params.bits);
  }
}

}  // namespace hrpp
