// The two reads of render_shade that are more than an array index, on the host's RenderScene:
// the light picked by its selection cdf (and a light's pick probability), the bilinear texture
// lookup and the material's textures at a hit. Mirrors of pick_light, light_pick_prob,
// sample_texture and textured_material in shaders/render_shade.comp
// and shaders/lib/render_bindings.glsl, operation for operation (the arithmetic
// itself is shared: surface_hit.h); tests/cpu_render_test.cpp holds them to the device.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "render/render_scene.h"

namespace hrpp {

// Light index with probability cdf[i] - cdf[i - 1] (rs.lights not empty); prob: that
// probability.
std::uint32_t pick_light(const RenderScene& rs, float u, float& prob);
// The probability that pick_light picks light i.
float pick_prob(const RenderScene& rs, std::uint32_t i);

// Texture `index` at uv as linear RGB: bilinear, repeat wrap, decoded from sRGB or not.
glm::vec3 sample_texture(const RenderScene& rs, int index, glm::vec2 uv, bool srgb);
// Material m at uv with its metallic-roughness and emissive textures applied.
gpu::GpuMaterial textured_material(const RenderScene& rs, gpu::GpuMaterial m, glm::vec2 uv);

}  // namespace hrpp
