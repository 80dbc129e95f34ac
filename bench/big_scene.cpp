// Resource limits: a generated scene of several million triangles (default 4M, a soup of small
// random triangles in a 100³ box) against the device's storage-buffer range (lavapipe: 128 MiB
// per binding). Prints the GPU layout's array sizes next to the device limits, then either the
// trace speed of a batch of rays (the scene fits) or the error the tracer gives and how long
// it took to come (the scene does not fit: it must come before any GPU work). Not a test.
//   bench_big_scene [--triangles N] [--rays R] [--device D]
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "common/error.h"
#include "gpu/gpu_tracer.h"
#include "gpu/vulkan_context.h"
#include "scene/scene.h"

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

double mib(std::size_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

}  // namespace

int main(int argc, char** argv) {
  std::size_t triangles = 4'000'000, rays = 100'000;
  hrpp::VulkanOptions vk;
  CLI::App app{"Resource limits: a multi-million-triangle scene on the Vulkan device"};
  app.add_option("--triangles", triangles, "Triangles to generate")->capture_default_str();
  app.add_option("--rays", rays, "Rays traced when the scene fits")->capture_default_str();
  app.add_option("--device", vk.device, "Vulkan device (index or name substring)");
  CLI11_PARSE(app, argc, argv);

  auto t0 = std::chrono::steady_clock::now();
  hrpp::Scene scene;
  scene.name = "soup";
  scene.materials.emplace_back();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(0.0f, 100.0f), off(-0.05f, 0.05f);
  scene.triangles.reserve(triangles);
  for (std::size_t i = 0; i < triangles; ++i) {
    const glm::vec3 c(pos(rng), pos(rng), pos(rng));
    scene.triangles.push_back({c + glm::vec3(off(rng), off(rng), off(rng)),
                               c + glm::vec3(off(rng), off(rng), off(rng)),
                               c + glm::vec3(off(rng), off(rng), off(rng))});
  }
  scene.shading.resize(triangles);
  std::printf("scene       %zu triangles generated in %.0f ms\n", triangles, ms_since(t0));
  t0 = std::chrono::steady_clock::now();
  const hrpp::GpuBvh bvh = hrpp::make_gpu_layout(hrpp::build_bvh(scene), scene);
  std::printf(
      "bvh         built and laid out in %.0f ms: nodes %.1f MiB, leaves %.1f MiB, "
      "triangles %.1f MiB (total %.1f MiB)\n",
      ms_since(t0), mib(bvh.nodes.size() * sizeof(hrpp::gpu::BvhNode)),
      mib(bvh.leaves.size() * sizeof(hrpp::gpu::BvhLeaf)),
      mib(bvh.triangles.size() * sizeof(hrpp::gpu::TriangleRecord)), mib(bvh.bytes()));
  try {
    hrpp::VulkanContext ctx(vk);
    const hrpp::DeviceInfo& d = ctx.info();
    std::printf("device      %s (%s): maxStorageBufferRange %.0f MiB, maxTexelBufferElements %u\n",
                d.name.c_str(), d.driver.c_str(), mib(d.max_storage_buffer_range),
                d.max_texel_buffer_elements);
    t0 = std::chrono::steady_clock::now();
    hrpp::GpuTracer tracer(ctx, bvh);
    std::printf("upload      %.0f ms: the scene fits\n", ms_since(t0));
    std::vector<hrpp::gpu::Ray> batch(rays);
    std::uniform_real_distribution<float> dir(-1.0f, 1.0f);
    for (auto& r : batch)
      r = {{pos(rng), pos(rng), pos(rng)}, 0.0f, {dir(rng), dir(rng), dir(rng)}, 1e30f};
    tracer.warm_up();
    const hrpp::GpuTraceResult res = tracer.trace(batch, false);
    std::printf("trace       %zu rays in %.1f ms kernel time: %.2f Mrays/s, %llu hits\n", rays,
                res.kernel_ms, static_cast<double>(rays) / (res.kernel_ms * 1e3),
                static_cast<unsigned long long>(res.counters.hits));
  } catch (const hrpp::Error& e) {
    std::printf("result      refused after %.0f ms: %s\n", ms_since(t0), e.what());
  }
  return 0;
}
