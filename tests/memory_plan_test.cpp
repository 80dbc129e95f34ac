// The device-memory checks made before any upload (host/vk/memory_plan.h) against small
// made-up limits, and the one byte formatter (host/common/bytes.h).
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "error_of.h"
#include "common/bytes.h"
#include "common/error.h"
#include "kernels/device_bvh.h"
#include "vk/memory_plan.h"

namespace hrpp {
namespace {

constexpr std::uint64_t kMiB = 1024 * 1024;

// lavapipe's limits with a heap of 1 GiB.
MemoryLimits lavapipe_like() {
  MemoryLimits m;
  m.storage_range = 128 * kMiB;
  m.texel_elements = 134217728;  // 2 GiB of 16-byte texels
  m.allocation = 2048 * kMiB;
  m.buffer = 4096 * kMiB;
  m.heap = 1024 * kMiB;
  m.heap_name = "memory heap";
  return m;
}

TEST(FormatBytes, PicksTheUnitAndRounds) {
  EXPECT_EQ(format_bytes(0), "0 bytes");
  EXPECT_EQ(format_bytes(1023), "1023 bytes");
  EXPECT_EQ(format_bytes(1024), "1.0 KiB");
  EXPECT_EQ(format_bytes(352 * 1024), "352.0 KiB");
  EXPECT_EQ(format_bytes(kMiB - 1), "1024.0 KiB");
  EXPECT_EQ(format_bytes(kMiB), "1.00 MiB");
  EXPECT_EQ(format_bytes(191929344), "183.04 MiB");
  EXPECT_EQ(format_bytes(2048 * kMiB), "2.00 GiB");
  EXPECT_EQ(format_bytes(~std::uint64_t{0}), "17179869184.00 GiB");
}

TEST(MemoryPlan, EachBindingHasItsOwnLimit) {
  const MemoryLimits m = lavapipe_like();
  std::string name;
  EXPECT_EQ(max_buffer_bytes(BufferBinding::kStorage, m, &name), 128 * kMiB);
  EXPECT_EQ(name, "maxStorageBufferRange");
  EXPECT_EQ(max_buffer_bytes(BufferBinding::kTexelOnly, m, &name), 2048 * kMiB);
  MemoryLimits small_alloc = m;
  small_alloc.allocation = 1000 * kMiB;  // below the texel range: the allocation limit rules
  EXPECT_EQ(max_buffer_bytes(BufferBinding::kTexelOnly, small_alloc, &name), 1000 * kMiB);
  EXPECT_EQ(name, "maxMemoryAllocationSize");
  small_alloc.buffer = 999 * kMiB;
  EXPECT_EQ(max_buffer_bytes(BufferBinding::kTexelOnly, small_alloc, &name), 999 * kMiB);
  EXPECT_EQ(name, "maxBufferSize");
}

// The triangle records are three planes of one texel a triangle (kernels/device_bvh.h): a BVH of n
// triangles needs n texels of each, where one array of 3-texel records needed 3n, so scenes up
// to maxTexelBufferElements triangles fit.
TEST(MemoryPlan, TrianglePlanesNeedOneTexelATriangle) {
  GpuBvh bvh;
  bvh.nodes.resize(1);
  bvh.leaves.resize(1);
  bvh.triangles.resize(100);
  const std::vector<BufferNeed> needs = DeviceBvh::buffer_needs(bvh);
  int planes = 0;
  for (const BufferNeed& n : needs) {
    EXPECT_EQ(n.binding, BufferBinding::kTexelOnly) << n.name;
    if (n.name.rfind("BVH triangle plane", 0) != 0) continue;
    ++planes;
    EXPECT_EQ(n.bytes, 100u * 16u) << n.name;
  }
  EXPECT_EQ(planes, 3);
  MemoryLimits m = lavapipe_like();
  m.texel_elements = 150;  // 100 records fit as planes, not as 300 texels of one array
  check_fits("the BVH", needs, m);
  m.texel_elements = 99;
  EXPECT_NE(test::error_of([&] { check_fits("the BVH", needs, m); })
                .find("BVH triangle plane 0 is 1.6 KiB (1600 bytes), over the device's "
                      "maxTexelBufferElements"),
            std::string::npos);
}

TEST(MemoryPlan, TexelOnlyArraysPassTheStorageRange) {
  const MemoryLimits m = lavapipe_like();
  const BufferNeed nodes{"BVH node array", 183 * kMiB, BufferBinding::kTexelOnly};
  EXPECT_NO_THROW(check_buffer(nodes, m));
  BufferNeed as_storage = nodes;
  as_storage.binding = BufferBinding::kStorage;
  const std::string e = test::error_of([&] { check_buffer(as_storage, m); });
  EXPECT_NE(e.find("BVH node array is 183.00 MiB (191889408 bytes)"), std::string::npos) << e;
  EXPECT_NE(e.find("maxStorageBufferRange of 128.00 MiB"), std::string::npos) << e;
  // Exactly at the limit fits; one byte over does not.
  EXPECT_NO_THROW(check_buffer({"a", 2048 * kMiB, BufferBinding::kTexelOnly}, m));
  const std::string over = test::error_of([&] { check_buffer({"a", 2048 * kMiB + 1, BufferBinding::kTexelOnly}, m); });
  EXPECT_NE(over.find("maxTexelBufferElements"), std::string::npos) << over;
}

TEST(MemoryPlan, TheSumMustFitTheHeap) {
  const MemoryLimits m = lavapipe_like();
  std::vector<BufferNeed> needs{{"BVH node array", 600 * kMiB, BufferBinding::kTexelOnly},
                                {"shading triangles", 424 * kMiB, BufferBinding::kTexelOnly},
                                {"image", 0}};
  EXPECT_EQ(total_bytes(needs), 1024 * kMiB);
  EXPECT_NO_THROW(check_fits("scene 'x'", needs, m));  // exactly the heap
  needs.push_back({"render queues", 64});
  const std::string e = test::error_of([&] { check_fits("scene 'x'", needs, m); });
  EXPECT_EQ(e,
            "scene 'x' needs 1.00 GiB (1073741888 bytes) of device memory in 4 buffers (largest: "
            "BVH node array 600.00 MiB, shading triangles 424.00 MiB, render queues 64 bytes), "
            "more than the device's memory heap of 1.00 GiB (1073741824 bytes)");
  EXPECT_EQ(e.find('\n'), std::string::npos);
}

TEST(MemoryPlan, OneBufferOverItsLimitIsNamedBeforeTheSum) {
  MemoryLimits m = lavapipe_like();
  m.heap = 16;  // the sum would fail too: the buffer's own limit is the first error
  const std::vector<BufferNeed> needs{{"node of triangle", 129 * kMiB}};
  const std::string e = test::error_of([&] { check_fits("scene 'x'", needs, m); });
  EXPECT_EQ(e.rfind("node of triangle is 129.00 MiB", 0), 0u) << e;
}

}  // namespace
}  // namespace hrpp
