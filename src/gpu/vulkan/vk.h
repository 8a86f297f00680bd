#pragma once
// The one place that includes Vulkan-Hpp, so that every translation unit
// sees the same configuration (these macros change class layouts).
//
// No dynamic-loader tool: gpu::LoaderLibrary opens the Vulkan loader itself
// at run time, so the binary starts (and the CPU renderers work) on a
// machine without libvulkan, and the error can name what was missing.
#define VULKAN_HPP_ENABLE_DYNAMIC_LOADER_TOOL 0
// Plain aggregates: create-info structs are written with designated initializers.
#define VULKAN_HPP_NO_STRUCT_CONSTRUCTORS
#include <vulkan/vulkan_raii.hpp>
