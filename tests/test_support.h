#pragma once
// Shared by the C++ tests: where the committed scenes and references live.
#include <filesystem>
#include <string>

#include "scene/scene.h"
#include "scene/scene_loader.h"

namespace rt::test {

inline std::filesystem::path sourceDir() { return RT_SOURCE_DIR; }
inline std::filesystem::path scenePath(const std::string& name) { return sourceDir() / "scenes" / (name + ".json"); }
inline Scene loadNamedScene(const std::string& name) { return loadScene(scenePath(name)); }

inline constexpr const char* kSceneNames[] = {"default", "random20", "random100"};

// The committed corpus of uneven sizes and density (scripts/rtbench/scenes.py):
// a ground sphere of radius 1000, clusters, a crowd on a huge sphere, heavy-tailed
// radii, nests of spheres inside spheres.
inline constexpr const char* kCorpusSceneNames[] = {"ground500", "clusters500", "crowd500", "heavytail500",
                                                    "nested200"};

}  // namespace rt::test
