// Interface of the wavefront path tracer's kernels (shaders/render_generate.comp,
// render_shade.comp, render_accumulate.comp) and of the shading code they share with the CPU
// reference renderer (path_vertex.h): binding slots, specialization constants, push
// constants and every struct they share with host/render/. One definition; the host
// static_asserts the sizes (host/render/render_scene.cpp).
//
// The ray and hit arrays are the trace kernels' own (GpuTracer::ray_buffer / hit_buffer): the
// renderer writes rays there and reads hits back, the traversal stays in shaders/lib/
// trace_kernel.glsl only.
#ifndef HRPP_RENDER_INTERFACE_H
#define HRPP_RENDER_INTERFACE_H

#include "gpu_types.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

#define HRPP_RENDER_WORKGROUP_SIZE 64

// Every render kernel has the same set layout (each uses what it needs).
#define HRPP_RENDER_BINDING_PARAMS 0           // RenderParams (one)
#define HRPP_RENDER_BINDING_PATHS 1            // PathState per ray of the current wavefront
#define HRPP_RENDER_BINDING_NEXT_PATHS 2       // PathState of the continuation rays
#define HRPP_RENDER_BINDING_RAYS 3             // the tracer's ray array (generate writes it)
#define HRPP_RENDER_BINDING_HITS 4             // the tracer's hit-all hits (uniform texel buffer)
#define HRPP_RENDER_BINDING_NEXT_RAYS 5        // continuation rays (copied to RAYS)
#define HRPP_RENDER_BINDING_SHADOW_RAYS 6      // the tracer's hit-any ray array (shade writes it)
#define HRPP_RENDER_BINDING_SHADOWS 7          // ShadowRecord per shadow ray
#define HRPP_RENDER_BINDING_IMAGE 8            // vec4 radiance sum per pixel
#define HRPP_RENDER_BINDING_QUEUES 9           // RenderQueues
#define HRPP_RENDER_BINDING_SHADE_TRIANGLES 10  // uniform texel buffer: ShadeIndex per triangle
#define HRPP_RENDER_BINDING_MATERIALS 11       // uniform texel buffer: GpuMaterial
#define HRPP_RENDER_BINDING_LIGHTS 12          // uniform texel buffer: GpuLight
#define HRPP_RENDER_BINDING_TEXTURES 13        // GpuTexture
#define HRPP_RENDER_BINDING_TEXELS 14          // RGBA8 texels of every texture, one uint each
#define HRPP_RENDER_BINDING_RAY_TEXELS 15      // uniform texel buffer over RAYS (shade reads)
#define HRPP_RENDER_BINDING_PATH_TEXELS 16     // uniform texel buffer over PATHS (shade reads)
#define HRPP_RENDER_BINDING_SHADOW_HITS 17     // the tracer's hit-any hits (uniform texel buffer)
#define HRPP_RENDER_BINDING_SHADE_VERTICES 18  // uniform texel buffer: ShadeVertex
#define HRPP_RENDER_BINDING_SHADE_ATTRIBUTES 19  // uniform texel buffer: ShadeAttributes
#define HRPP_RENDER_BINDING_COUNT 20
// Read-only arrays are uniform texel buffers (R32G32B32A32_UINT): on lavapipe a texel fetch
// gathers the lanes' 16-byte records at once where a storage-buffer load with per-lane
// addresses is a loop over the lanes (host/vk/texel_view.h).

// Specialization constant ids (bool): what the scene needs. A kernel compiled with one off has
// that code removed (llvmpipe folds the constant before code generation).
#define HRPP_FEATURE_TEXTURES 0
#define HRPP_FEATURE_EMISSIVE_TRIANGLES 1
#define HRPP_FEATURE_POINT_LIGHTS 2
#define HRPP_FEATURE_SPOT_LIGHTS 3
#define HRPP_FEATURE_DIRECTIONAL_LIGHTS 4
#define HRPP_FEATURE_ENVIRONMENT 5
#define HRPP_FEATURE_METAL 6
#define HRPP_FEATURE_GLASS 7
#define HRPP_FEATURE_SPECULAR_LAYER 8
#define HRPP_FEATURE_MATERIAL_TEXTURES 9  // metallicRoughnessTexture, emissiveTexture
#define HRPP_FEATURE_COUNT 10
#ifdef __cplusplus
// The CPU reference renderer (host/cpu_render/) compiles every feature in: a feature that is
// off only removes code the scene's data cannot reach (make_render_scene sets them).
inline constexpr bool kTextures = true;
inline constexpr bool kEmissiveTriangles = true;
inline constexpr bool kPointLights = true;
inline constexpr bool kSpotLights = true;
inline constexpr bool kDirectionalLights = true;
inline constexpr bool kEnvironment = true;
inline constexpr bool kMetal = true;
inline constexpr bool kGlass = true;
inline constexpr bool kSpecularLayer = true;
inline constexpr bool kMaterialTextures = true;
#endif

#define HRPP_LIGHT_TRIANGLE 0u
#define HRPP_LIGHT_POINT 1u
#define HRPP_LIGHT_SPOT 2u
#define HRPP_LIGHT_DIRECTIONAL 3u

// How light reaches a path vertex from emissive triangles (RenderParams.light_strategy,
// --light-sampling): next-event estimation and BSDF sampling combined with the power heuristic
// (Veach and Guibas 1995), or one of them alone. Delta lights (point, spot, directional) are
// always sampled; the environment is found by BSDF-sampled rays (path_vertex.h).
#define HRPP_LIGHTS_MIS 0u
#define HRPP_LIGHTS_NEE 1u   // light sampling alone: emission a BSDF ray finds is not counted
#define HRPP_LIGHTS_BSDF 2u  // BSDF sampling alone: no shadow rays to emissive triangles

// Where a path's random numbers come from (RenderParams.sampler_kind, --sampler): Owen-scrambled
// Sobol points (sobol_sampler.h), or independent PCG streams (rng.h).
#define HRPP_SAMPLER_INDEPENDENT 0u
#define HRPP_SAMPLER_SOBOL 1u

// Per-frame constants.
struct RenderParams {
  uint width;
  uint height;
  uint seed;
  uint max_depth;      // surface interactions per path (1: direct light only)
  vec4 cam_position;   // w: tan(yfov / 2)
  vec4 cam_forward;    // w: aspect (width / height)
  vec4 cam_up;
  vec4 cam_right;
  vec4 environment;    // rgb: constant environment radiance
  uint light_count;    // entries of the light array (selection by its cdf)
  uint rr_depth;       // Russian roulette from this depth on
  uint trace_any_group_rays;  // rays per workgroup of the shadow trace (its indirect dispatch)
  uint light_strategy;        // HRPP_LIGHTS_*
  uint sampler_kind;          // HRPP_SAMPLER_* (sampler is a GLSL keyword)
  uint pad0;
  uint pad1;
  uint pad2;
};

// One path of the wavefront (its ray is rays[i] of the same index).
struct PathState {
  vec3 throughput;
  uint pixel;
  uint sample_index;
  uint depth;     // surface interactions so far (camera ray: 0)
  uint specular;  // 1: the last bounce was a delta lobe (emission is then counted on hit)
  float pdf;      // solid-angle pdf of the BSDF sample that made the path's ray (camera ray: 0)
};

// A shadow ray's payload: added to image[pixel] when the ray is unoccluded.
struct ShadowRecord {
  vec3 contribution;
  uint pixel;
};

// The queues of one bounce of a wavefront, in one buffer: atomic counters the kernels fill,
// the indirect dispatch arguments render_shade makes of the shadow queue, and completion
// counts. The host resets it (kRenderQueuesStart) at the start of the bounce's command buffer,
// reads it back after the submit and compares the completion counts with the work submitted
// (docs/DEVICES.md, "Loop limiter").
#define HRPP_RENDER_DONE_GENERATE 0
#define HRPP_RENDER_DONE_SHADE 1
#define HRPP_RENDER_DONE_ACCUMULATE 2
struct RenderQueues {
  uint next_rays;    // continuation rays written by shade
  uint shadow_rays;  // shadow rays written by shade (the count trace_any and accumulate run on)
  uint pad0;
  uint pad1;
  uint done[4];      // items each kernel finished, by HRPP_RENDER_DONE_*
  uint trace_any_groups[3];   // VkDispatchIndirectCommand of the shadow trace
  uint pad2;
  uint accumulate_groups[3];  // VkDispatchIndirectCommand of render_accumulate
  uint pad3;
};

struct RenderPushConstants {
  uint first_pixel;  // generate: pixel of item 0 of this wavefront
  uint count;        // generate, shade: items in this dispatch (accumulate: queues.shadow_rays)
  uint sample_index; // generate: sample index
  uint bounce;       // shade: depth of the paths it shades
};

// Shading data of one triangle (by triangle id) as the shading code reads it, assembled from
// its ShadeIndex and three ShadeVertex records (shade_triangle_of).
// n0.w, n1.w, n2.w: the vertex colours (HRPP_VERTEX_COLORS) as the float value of 0xBBGGRR
// (below 2^24, so exact).
#define HRPP_VERTEX_NORMALS 1u
#define HRPP_VERTEX_COLORS 2u
struct ShadeTriangle {
  vec3 v0;
  uint material;
  vec3 v1;
  uint vertex_data;  // HRPP_VERTEX_NORMALS | HRPP_VERTEX_COLORS: which of n and colour are set
  vec3 v2;
  uint light;  // emissive triangles: 1 + the index of the triangle's light; 0: not a light
  vec4 n0;
  vec4 n1;
  vec4 n2;
  vec4 uv01;
  vec4 uv2;
};

// The shading data as stored: indexed, so a corner that triangles share is stored once.
// ShadeIndex, one 16-byte texel per triangle id: its corners' vertex indices and
// material | HRPP_SHADE_ATTRIBUTES | vertex_data << HRPP_SHADE_DATA_SHIFT (materials below 2^29).
// A vertex is a ShadeVertex and, when the scene has any normal, colour or uv (the triangle's
// HRPP_SHADE_ATTRIBUTES), a ShadeAttributes of the same index; without, the attributes are
// ShadeAttributes' defaults (no normal, white, uv 0), which the shading reads without a fetch.
#define HRPP_SHADE_DATA_SHIFT 30u
#define HRPP_SHADE_ATTRIBUTES 0x20000000u
#define HRPP_SHADE_MATERIAL_MASK 0x1FFFFFFFu
#define HRPP_NO_VERTEX_COLOR 16777215.0f // 0xFFFFFF as a float: white (scene.h kNoVertexColor)
struct ShadeIndex {
  uint corner0;
  uint corner1;
  uint corner2;
  uint material_data;
};

// One texel. `light` is the triangle's (ShadeTriangle::light) in its corner 0 and 0 in corners 1
// and 2, so an emissive triangle's corner 0 is shared only by triangles with the same light.
struct ShadeVertex {
  vec3 position;
  uint light;
};

// Two texels: normal.xyz colour (ShadeTriangle::n0) | uv.xy 0 0.
struct ShadeAttributes {
  vec4 normal_color;
  vec4 uv;
};

// GpuMaterial::flags: only the front emits (pbrt's one-sided area lights), the side that
// cross(v1 - v0, v2 - v0) points to.
#define HRPP_MATERIAL_ONE_SIDED 1u

struct GpuMaterial {
  vec3 base_color;
  int texture;  // index into the GpuTexture array, -1: none
  vec3 emission;
  float metallic;
  float roughness;
  float transmission;
  float ior;
  uint flags;  // HRPP_MATERIAL_*
  // The dielectric's specular layer (glTF's Appendix B with KHR_materials_specular): Schlick's
  // Fresnel between specular_f0 and specular_f90; f90 0: none, a Lambertian diffuse.
  vec3 specular_f0;
  float specular_f90;
  // glTF's metallicRoughnessTexture (linear; B scales metallic, G roughness) and emissiveTexture
  // (sRGB; it scales emission): indices into the GpuTexture array, -1: none.
  int metallic_roughness_texture;
  int emissive_texture;
  int pad0;
  int pad1;
};

// Light for next-event estimation, chosen with probability cdf - previous cdf (by power).
//   triangle:    position = v0, dir = v1 - v0, edge2 = v2 - v0, color = radiance; cos_inner 1:
//                one-sided (only the side dir × edge2 points to emits), 0: two-sided
//   point:       position, color = intensity
//   spot:        position, dir = the direction light travels, color = intensity, cones
//   directional: dir = the direction light travels, color = irradiance
struct GpuLight {
  vec3 position;
  uint type;  // HRPP_LIGHT_*
  vec3 color;
  float cdf;
  vec3 dir;
  float cos_inner;
  vec3 edge2;
  float cos_outer;
};

struct GpuTexture {
  uint offset;  // first texel in the texel array
  int width;
  int height;
  uint pad;
};

// render_offset_rays, a check kernel: the ray offsets of shaders/lib/offset_ray.glsl on arrays,
// one case per invocation, compared with the C++ mirror (host/trace/offset_ray.h) bit for bit.
#define HRPP_OFFSET_RAYS_BINDING_CASES 0    // OffsetRayCase per invocation
#define HRPP_OFFSET_RAYS_BINDING_RESULTS 1  // OffsetRayResult per invocation
#define HRPP_OFFSET_RAYS_BINDING_COUNT 2

struct OffsetRayCase {
  vec4 p;   // xyz: surface point
  vec4 n;   // xyz: its normal on the side the ray leaves into
  vec4 q;   // xyz: point on a light
  vec4 nq;  // xyz: the light's normal on p's side (zero: a point light)
};

struct OffsetRayResult {
  vec4 origin;  // xyz: offset_ray_origin(p, n)
  Ray shadow;   // shadow_ray_to(p, n, q, nq)
};

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_RENDER_INTERFACE_H
