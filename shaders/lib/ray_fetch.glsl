// The ray array read through a uniform texel buffer at binding HRPP_RAYS_BINDING (an
// R32G32B32A32_UINT view, host/vk/texel_view.h): a Ray is 2 texels, its bits reinterpreted,
// never converted. Included by texel_fetch.glsl (the BVH kernels) and ray_query_kernel.glsl.
#ifndef HRPP_RAY_FETCH_GLSL
#define HRPP_RAY_FETCH_GLSL

#extension GL_EXT_samplerless_texture_functions : require

layout(set = 0, binding = HRPP_RAYS_BINDING) uniform utextureBuffer ray_texels;

Ray load_ray(uint index) {
  const int t = 2 * int(index);
  const uvec4 a = texelFetch(ray_texels, t);
  const uvec4 b = texelFetch(ray_texels, t + 1);
  return Ray(uintBitsToFloat(a.xyz), uintBitsToFloat(a.w), uintBitsToFloat(b.xyz),
             uintBitsToFloat(b.w));
}

#endif  // HRPP_RAY_FETCH_GLSL
