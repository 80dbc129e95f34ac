// The --stats JSON of a render: one nested object with the configuration, the device, the
// compiled-in features, device time per kernel, counters per ray class (hit-all: camera +
// bounce rays; hit-any: shadow rays) and totals, and the wall time.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "vk/memory_ledger.h"
#include "vk/vulkan_context.h"
#include "render/wavefront_renderer.h"

namespace hrpp {

nlohmann::json render_stats_json(const std::string& scene, const RenderConfig& config,
                                 const DeviceInfo& device, const RenderResult& result);

// The "memory" object of the stats: bytes allocated per named device buffer ("buffers"), their
// total, the peak total, the device heap they were checked against (vk/memory_plan.h), the
// memory mode and where each role's buffers live ("mode", "placement": placement_json). With
// `triangles` (the scene's), also each buffer's and the total's bytes per triangle
// ("bytes_per_triangle", "total_bytes_per_triangle") and the host's peak resident memory
// ("host_peak_rss_bytes", "host_peak_rss_bytes_per_triangle"; common/peak_rss.h).
nlohmann::json memory_json(const MemoryReport& memory, std::size_t triangles = 0);

// One terminal line: "<total> in <n> buffers (peak <peak>, heap <heap>); largest <name> <size>;
// <placement_text>", with `triangles`, then "; <b> bytes/triangle, host peak RSS <rss> (<b>
// bytes/triangle)".
std::string memory_text(const MemoryReport& memory, std::size_t triangles = 0);

// {"device": {"type", "heap", "flags", "mapped"}, "host_shared": {...}} (vk/memory_placement.h).
nlohmann::json placement_json(const MemoryPlacement& placement);

// "staged: device buffers in type 1 (device-local) heap 0, host_shared buffers in type 3
// (host-visible, coherent, cached) heap 1".
std::string placement_text(const MemoryPlacement& placement);

// The same as lines of text for the terminal.
std::string render_stats_text(const RenderConfig& config, const RenderResult& result);

}  // namespace hrpp
