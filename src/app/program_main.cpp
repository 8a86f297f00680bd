#include "app/program_main.h"

#include <iostream>

#include "app/cli.h"
#include "gpu/present/window_presentation.h"
#include "gpu/vulkan/device_info.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"

namespace rt {

int runProgram(std::string_view program, int argc, char** argv, const std::function<int(const RunConfig&)>& run) {
  auto parsed = parseCommandLine(argc, argv);
  if (auto* exit = std::get_if<CliExit>(&parsed)) {
    std::cout << exit->output;
    std::cerr << exit->error;
    return exit->code;
  }
  const auto fail = [&](std::string_view what, const std::exception& e, int code) {
    std::cerr << program << ": " << what << e.what() << "\n";
    return code;
  };
  try {
    return run(std::get<RunConfig>(parsed));
  } catch (const SceneError& e) {
    return fail("invalid scene: ", e, kExitBadInput);
  } catch (const RendererUnavailable& e) {
    return fail("", e, kExitBadInput);
  } catch (const gpu::WindowUnavailable& e) {
    return fail("no window: ", e, kExitNoDevice);
  } catch (const gpu::FeatureUnavailable& e) {
    return fail("", e, kExitBadInput);
  } catch (const gpu::DeviceUnavailable& e) {
    return fail("no Vulkan device: ", e, kExitNoDevice);
  } catch (const gpu::DeviceError& e) {
    return fail("GPU error: ", e, kExitRuntimeError);
  } catch (const std::exception& e) {
    return fail("error: ", e, kExitRuntimeError);
  }
}

}  // namespace rt
