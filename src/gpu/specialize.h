#pragma once
// Applying a kernel's specialization constants to its SPIR-V before the
// driver sees it (SPIRV-Tools' optimizer; docs/architecture.md).
#include <cstdint>
#include <string>
#include <vector>

namespace wp {

// The kernel `code` (SPIR-V words) with specialization constant i set to
// values[i] and frozen, and the branches and functions those constants rule
// out removed. Drivers compile the result with no specialization info.
// `code` must be valid SPIR-V (the kernels glslang compiled at build time):
// the optimizer does not validate its input. Returns an empty vector, with the
// optimizer's messages in `error`, if the optimizer fails.
std::vector<uint32_t> specialize_kernel(const uint32_t* code, size_t words, const std::vector<uint32_t>& values,
                                        std::string& error);

}  // namespace wp
