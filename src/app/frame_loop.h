#pragma once
#include <exception>
#include <vector>

#include "app/frame_recorder.h"
#include "app/run_config.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace rt {

struct FrameLoopResult {
  std::vector<FrameRecord> records;   // the frames that completed
  std::vector<Image> savedFrames;     // one per config.saveFrames entry, same order
  std::exception_ptr failure;         // set when a frame threw; records keep what was done
};

// The windowless application loop: Update -> Render -> Present per frame,
// warm-up frames first. Everything the loop touches is allocated before it.
FrameLoopResult runFrameLoop(Renderer& renderer, const Scene& scene, const RunConfig& config);

}  // namespace rt
