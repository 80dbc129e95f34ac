#include "vk/float_controls.h"

#include "common/error.h"

namespace hrpp {

namespace {

// SPIR-V's numbers (the SPIR-V specification, sections 3.31 and 3.6 and the instruction list).
constexpr std::uint32_t kMagic = 0x07230203u;
constexpr std::uint32_t kHeaderWords = 5;
constexpr std::uint32_t kOpCapability = 17;
constexpr std::uint32_t kOpEntryPoint = 15;
constexpr std::uint32_t kCapabilityDenormPreserve = 4464;
constexpr std::uint32_t kExecutionModeDenormPreserve = 4459;
constexpr std::uint32_t kOpExecutionMode = 16;

std::uint32_t word_count(std::uint32_t w) { return w >> 16; }
std::uint32_t opcode(std::uint32_t w) { return w & 0xFFFFu; }
std::uint32_t instruction(std::uint32_t op, std::uint32_t words) { return words << 16 | op; }

}  // namespace

std::vector<std::uint32_t> with_denorm_preserve(std::span<const std::uint32_t> spirv) {
  const std::uint32_t version = spirv.size() > 1 ? spirv[1] : 0;
  if (spirv.size() < kHeaderWords || spirv[0] != kMagic || version < 0x00010400u)
    throw Error("with_denorm_preserve: not a SPIR-V 1.4+ module");
  std::vector<std::uint32_t> out(spirv.begin(), spirv.begin() + kHeaderWords);
  bool capability = false;
  std::vector<std::uint32_t> entries;  // the entry points' ids, their modes not yet written
  std::size_t moded = 0;
  for (std::size_t i = kHeaderWords; i < spirv.size();) {
    const std::uint32_t n = word_count(spirv[i]);
    if (n == 0 || i + n > spirv.size()) throw Error("with_denorm_preserve: truncated SPIR-V");
    const std::uint32_t op = opcode(spirv[i]);
    // Capabilities come first in a module: the new one goes before the first of them.
    if (op == kOpCapability && !capability) {
      out.insert(out.end(), {instruction(kOpCapability, 2), kCapabilityDenormPreserve});
      capability = true;
    }
    // Execution modes follow the last entry point.
    if (op != kOpEntryPoint) {
      for (; moded < entries.size(); ++moded)
        out.insert(out.end(), {instruction(kOpExecutionMode, 4), entries[moded],
                               kExecutionModeDenormPreserve, 32u});
    } else {
      entries.push_back(spirv[i + 2]);
    }
    out.insert(out.end(), spirv.begin() + i, spirv.begin() + i + n);
    i += n;
  }
  const bool entry = !entries.empty() && moded == entries.size();
  if (!capability || !entry) throw Error("with_denorm_preserve: SPIR-V without an entry point");
  return out;
}

}  // namespace hrpp
