// Byte counts as text, one way for every message, table and report of the codebase.
#pragma once

#include <cstdint>
#include <string>

namespace hrpp {

// "512 bytes", "352.0 KiB", "183.00 MiB", "2.00 GiB" (binary units; KiB below 1 MiB, MiB below
// 1 GiB). Exact counts, where a message needs them, are printed beside it by the caller.
std::string format_bytes(std::uint64_t bytes);

}  // namespace hrpp
