// What a scene's device buffers need, checked against what the device has, before anything is
// allocated or uploaded (docs/DEVICES.md, "Device memory"). Pure functions over numbers:
// tests hold them to small made-up limits without a device.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace hrpp {

struct DeviceInfo;

// How the kernels see a buffer, which decides the per-buffer limit that applies to it.
enum class BufferBinding {
  kStorage,    // bound as a storage buffer (and maybe as texel views too): maxStorageBufferRange
  kTexelOnly,  // read only through TexelViews (16-byte texels): maxTexelBufferElements
  kAddressOnly,  // reached only by its device address (an acceleration structure, its inputs
                 // and scratch): maxMemoryAllocationSize and maxBufferSize alone
};

struct BufferNeed {
  std::string name;  // as in errors and the stats' "memory" object
  std::uint64_t bytes = 0;
  BufferBinding binding = BufferBinding::kStorage;
};

// The device's limits on buffers and memory, in bytes (texel_elements in 16-byte texels).
struct MemoryLimits {
  std::uint64_t storage_range = 0;   // maxStorageBufferRange
  std::uint64_t texel_elements = 0;  // maxTexelBufferElements
  std::uint64_t allocation = 0;      // maxMemoryAllocationSize (one buffer is one allocation)
  std::uint64_t buffer = 0;          // maxBufferSize
  std::uint64_t heap = 0;            // the heap of the memory type buffers use, or its budget
  std::string heap_name;             // how the heap figure was found, for errors
};

MemoryLimits memory_limits(const DeviceInfo& device);

// The largest buffer of this binding the device allows, and the name of the limit that sets it.
std::uint64_t max_buffer_bytes(BufferBinding binding, const MemoryLimits& limits,
                               std::string* limit_name = nullptr);

// Throws hrpp::Error "<name> is <size> (<n> bytes), over the device's <limit> of <size>" when
// one buffer is bigger than its binding allows.
void check_buffer(const BufferNeed& need, const MemoryLimits& limits);

std::uint64_t total_bytes(std::span<const BufferNeed> needs);

// check_buffer for each, then the sum against the heap: throws hrpp::Error "<what> needs
// <size> (<n> bytes) of device memory in <k> buffers (largest: ...), more than the device's
// <heap>" naming `what` (the scene).
void check_fits(const std::string& what, std::span<const BufferNeed> needs,
                const MemoryLimits& limits);

}  // namespace hrpp
