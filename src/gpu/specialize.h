#pragma once
// Applying a kernel's specialization constants to its SPIR-V before the
// driver sees it (SPIRV-Tools' optimizer; docs/architecture.md).
#include <cstdint>
#include <string>
#include <vector>

namespace wp {

// How far the host folds a kernel's constants before the driver sees it.
enum class Folding {
  // Branches on the constants themselves: what the walks need. lavapipe
  // compiles the walks' loops 4-5 % longer (instructions run, counted by
  // callgrind) when the host has also rewritten their locals into SSA form.
  Branches,
  // The constants also propagated through the locals they flow into, so that
  // every branch they decide goes: what the shading kernels need, whose
  // material, texture and light code is most of a pipeline's creation time.
  ThroughLocals,
};

// The kernel `code` (SPIR-V words) with specialization constant i set to
// values[i] and frozen, and the branches and functions those constants rule
// out removed. Drivers compile the result with no specialization info.
// `code` must be valid SPIR-V (the kernels glslang compiled at build time):
// the optimizer does not validate its input. Returns an empty vector, with the
// optimizer's messages in `error`, if the optimizer fails.
std::vector<uint32_t> specialize_kernel(const uint32_t* code, size_t words, const std::vector<uint32_t>& values,
                                        std::string& error, Folding folding = Folding::ThroughLocals);

}  // namespace wp
