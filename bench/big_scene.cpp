// Resource limits: a generated scene of several million triangles (default 4M, a soup of small
// random triangles in a 100³ box) against the device's buffer limits and memory heap
// (vk/memory_plan.h). Prints the device's limits, each array the tracer allocates with its
// binding's limit, and their sum against the heap, then either the trace speed of a batch of
// rays (the scene fits) or the error the tracer gives and how long it took to come (the scene
// does not fit: it must come before any GPU work). Not a test.
//   bench_big_scene [--triangles N] [--rays R] [--device D]
// HRPP_DEVICE_HEAP_MIB=N caps the heap, to see the refusal of a scene that does not fit.
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "common/bytes.h"
#include "common/error.h"
#include "gpu/gpu_tracer.h"
#include "vk/memory_plan.h"
#include "vk/vulkan_context.h"
#include "scene/triangle_soup.h"

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

using hrpp::format_bytes;

void print_limits(const hrpp::DeviceInfo& d) {
  const hrpp::MemoryLimits m = hrpp::memory_limits(d);
  std::printf("device      %s (%s)\n", d.name.c_str(), d.driver.c_str());
  std::printf("limits      maxStorageBufferRange %s, maxTexelBufferElements %u (%s), "
              "maxMemoryAllocationSize %s, maxBufferSize %s\n",
              format_bytes(m.storage_range).c_str(), d.max_texel_buffer_elements,
              format_bytes(m.texel_elements * 16).c_str(), format_bytes(m.allocation).c_str(),
              format_bytes(m.buffer).c_str());
  std::printf("heap        %s: %s (the device reports %s)\n", m.heap_name.c_str(),
              format_bytes(m.heap).c_str(), format_bytes(d.reported_heap_bytes).c_str());
}

// Each array the tracer needs, with the limit of its binding, and the sum against the heap.
void print_plan(const hrpp::GpuBvh& bvh, std::size_t rays, const hrpp::DeviceInfo& d) {
  const hrpp::MemoryLimits m = hrpp::memory_limits(d);
  const std::vector<hrpp::BufferNeed> needs = hrpp::GpuTracer::buffer_needs(bvh, rays);
  for (const hrpp::BufferNeed& n : needs) {
    std::string limit;
    const std::uint64_t most = hrpp::max_buffer_bytes(n.binding, m, &limit);
    std::printf("  %-22s %12s  (%s; limit %s: %s)\n", n.name.c_str(), format_bytes(n.bytes).c_str(),
                n.binding == hrpp::BufferBinding::kStorage ? "storage" : "texel views only",
                limit.c_str(), format_bytes(most).c_str());
  }
  std::printf("  %-22s %12s  of the heap's %s\n", "total",
              format_bytes(hrpp::total_bytes(needs)).c_str(), format_bytes(m.heap).c_str());
}

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
  const hrpp::Scene scene = hrpp::make_triangle_soup(triangles, 7);
  std::printf("scene       %zu triangles generated in %.0f ms\n", triangles, ms_since(t0));
  t0 = std::chrono::steady_clock::now();
  const hrpp::GpuBvh bvh = hrpp::make_gpu_layout(hrpp::build_bvh(scene), scene);
  std::printf("bvh         built and laid out in %.0f ms (%s)\n", ms_since(t0),
              format_bytes(bvh.bytes()).c_str());
  try {
    hrpp::VulkanContext ctx(vk);
    print_limits(ctx.info());
    std::printf("buffers     with %zu rays resident:\n", rays);
    print_plan(bvh, rays, ctx.info());
    t0 = std::chrono::steady_clock::now();
    hrpp::GpuTracer tracer(ctx, bvh);
    std::printf("upload      %.0f ms: the scene fits (%s allocated)\n", ms_since(t0),
                format_bytes(ctx.memory().report().total).c_str());
    std::vector<hrpp::gpu::Ray> batch(rays);
    std::mt19937 rng(8);  // random rays from inside the soup's box
    std::uniform_real_distribution<float> pos(0.0f, 100.0f), dir(-1.0f, 1.0f);
    for (auto& r : batch)
      r = {{pos(rng), pos(rng), pos(rng)}, 0.0f, {dir(rng), dir(rng), dir(rng)}, 1e30f};
    tracer.warm_up();
    const hrpp::GpuTraceResult res = tracer.trace(batch, hrpp::QueryKind::kClosest);
    std::printf("trace       %zu rays in %.1f ms kernel time: %.2f Mrays/s, %llu hits\n", rays,
                res.kernel_ms, static_cast<double>(rays) / (res.kernel_ms * 1e3),
                static_cast<unsigned long long>(res.counters.hits));
  } catch (const hrpp::Error& e) {
    std::printf("result      refused after %.0f ms: %s\n", ms_since(t0), e.what());
  }
  return 0;
}
