#include "gpu/specialize.h"

#include <spirv-tools/optimizer.hpp>

#include <unordered_map>

namespace wp {

// Why here and not in the driver: the kernels keep every material, texture
// and feature of every scene behind branches on specialization constants,
// and a driver may inline every call before it folds those constants
// (lavapipe does), so code a scene can never run still costs pipeline
// creation. The constants are folded here, (Folding::ThroughLocals) the
// locals they flow through promoted to SSA values and propagated, and the
// branches, blocks and functions they rule out removed; the driver optimizes
// the rest itself.
std::vector<uint32_t> specialize_kernel(const uint32_t* code, size_t words, const std::vector<uint32_t>& values,
                                        std::string& error, Folding folding) {
  spvtools::Optimizer optimizer(SPV_ENV_VULKAN_1_1);
  optimizer.SetMessageConsumer([&error](spv_message_level_t level, const char*, const spv_position_t& at, const char* message) {
    if (level <= SPV_MSG_ERROR) error += "SPIR-V word " + std::to_string(at.index) + ": " + message + "; ";
  });
  std::unordered_map<uint32_t, std::vector<uint32_t>> byId;
  for (uint32_t id = 0; id < values.size(); ++id) byId[id] = {values[id]};
  optimizer.RegisterPass(spvtools::CreateSetSpecConstantDefaultValuePass(byId))
      .RegisterPass(spvtools::CreateFreezeSpecConstantValuePass())
      .RegisterPass(spvtools::CreateFoldSpecConstantOpAndCompositePass());
  if (folding == Folding::ThroughLocals) {
    optimizer.RegisterPass(spvtools::CreateSSARewritePass())
        .RegisterPass(spvtools::CreateCCPPass())
        .RegisterPass(spvtools::CreateSimplificationPass());
  }
  optimizer.RegisterPass(spvtools::CreateDeadBranchElimPass());
  if (folding == Folding::ThroughLocals) optimizer.RegisterPass(spvtools::CreateBlockMergePass());
  optimizer.RegisterPass(spvtools::CreateAggressiveDCEPass()).RegisterPass(spvtools::CreateEliminateDeadFunctionsPass());
  spvtools::OptimizerOptions options;
  options.set_run_validator(false);  // glslang's output; the tests validate what comes out (KernelSpecialization.*)
  std::vector<uint32_t> out;
  if (!optimizer.Run(code, words, &out, options)) return {};
  return out;
}

}  // namespace wp
