// reference.h — the CPU reference renderer. It runs the integrator through the
// very functions the kernels run (shaders/shared/*.glsl compiled as C++), one
// sample at a time instead of one stage at a time, on all cores with TBB.
#pragma once

#include "image/image.h"
#include "render/compiled_scene.h"
#include "render/render_control.h"
#include "util/progress.h"

namespace wp {

// Renders samples `range` of every pixel into `image` (which may hold
// earlier samples), pass by pass, calling `afterPass` between passes
// (render_control.h); returns the sample reached. threads <= 0: all cores.
// Throws RenderError if any traversal hit its step cap. Any BVH layout
// renders the same image; compile with reference_options for the one that is
// fastest here. Each pixel adds its samples in order, whatever the passes,
// so one range rendered in any number of passes gives the same sums.
uint32_t render_cpu(const CompiledScene& scene, int threads, ImageStats& image, SampleRange range, Progress& progress,
                    const PassHook& afterPass = {});
// All of the scene's samples, 0 to scene.spp, into a new image.
ImageStats render_cpu(const CompiledScene& scene, int threads, Progress& progress);

// `options` with the CPU reference's BVH layout: the binary tree, which a CPU
// walks about twice as fast as the wide one (built for lavapipe, where every
// iteration visits a node and tests a primitive and all eight children are
// tested at once), walked fused (trace_binary_fused: a few per cent faster
// here). Checking the kernels' wide tree against it also crosses two
// different trees, and their plain binary walk two different walks.
RenderOptions reference_options(RenderOptions options);

}  // namespace wp
