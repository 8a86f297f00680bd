#include "gpu/vulkan/device.h"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace rt::gpu {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr std::uint32_t kApiVersion = VK_MAKE_API_VERSION(0, kRequiredApiMajor, kRequiredApiMinor, 0);

std::string versionString(std::uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

// Prints and counts validation warnings and errors. Vulkan-Hpp declares
// the callback with the C types (Debian 12's 1.3.239) or, newer, with vk::
// types of the same layout (Debian 13's 1.4.309); a template whose
// parameter types are deduced from the member it is assigned to (see
// messengerCreateInfo) is one callback for both, without a cast between
// function types.
//
// The loader's own messages are printed, not counted: on a multiarch machine
// it reports every driver manifest of another architecture (arm64 or i386
// Mesa beside the amd64 one) as an error it then ignores. What the loader
// cannot get past fails the call it belongs to, and the count is for the
// validation layer's findings.
template <typename Severity, typename Types, typename CallbackData>
VKAPI_ATTR VkBool32 VKAPI_CALL countMessage(Severity severity, Types /*types*/, const CallbackData* data, void* user) {
  const bool error = (static_cast<VkDebugUtilsMessageSeverityFlagBitsEXT>(severity) &
                      VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) != 0;
  const bool fromLoader = data->pMessageIdName != nullptr && std::string_view(data->pMessageIdName) == "Loader Message";
  if (!fromLoader) static_cast<ValidationCounter*>(user)->add(error);
  std::fprintf(stderr, "vulkan %s%s: %s\n", fromLoader ? "loader " : "", error ? "error" : "warning",
               data->pMessage ? data->pMessage : "");
  return VK_FALSE;  // never abort the call: the count is what fails a test
}

vk::DebugUtilsMessengerCreateInfoEXT messengerCreateInfo(ValidationCounter& counter) {
  vk::DebugUtilsMessengerCreateInfoEXT info{.messageSeverity = vk::DebugUtilsMessageSeverityFlagBitsEXT::eWarning |
                                                               vk::DebugUtilsMessageSeverityFlagBitsEXT::eError,
                                            .messageType = vk::DebugUtilsMessageTypeFlagBitsEXT::eGeneral |
                                                           vk::DebugUtilsMessageTypeFlagBitsEXT::eValidation |
                                                           vk::DebugUtilsMessageTypeFlagBitsEXT::ePerformance,
                                            .pUserData = &counter};
  info.pfnUserCallback = &countMessage;  // the template's arguments come from the member's type
  return info;
}

bool hasLayer(const vk::raii::Context& context, std::string_view name) {
  const auto layers = context.enumerateInstanceLayerProperties();
  return std::ranges::any_of(layers, [&](const vk::LayerProperties& l) { return name == l.layerName.data(); });
}

bool hasExtension(const std::vector<vk::ExtensionProperties>& extensions, std::string_view name) {
  return std::ranges::any_of(extensions,
                             [&](const vk::ExtensionProperties& e) { return name == e.extensionName.data(); });
}

// What an instance enables (the names are static strings).
struct InstanceRequest {
  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  vk::InstanceCreateFlags flags;
  bool validationFeatures = false;  // VK_EXT_validation_features: synchronization validation
};

InstanceRequest instanceRequest(const vk::raii::Context& context, const ContextOptions& options) {
  const bool validation = options.validation;
  InstanceRequest request;
  const auto available = context.enumerateInstanceExtensionProperties();
  for (const std::string& name : options.surfaceExtensions) {
    if (!hasExtension(available, name)) {
      throw DeviceUnavailable("the Vulkan loader has no " + name + ", which the window's surface needs");
    }
    request.extensions.push_back(name.c_str());  // options outlive the instance's creation
  }
  // Portability drivers (MoltenVK) are listed only when asked for.
  if (hasExtension(context.enumerateInstanceExtensionProperties(), VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME)) {
    request.extensions.push_back(VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME);
    request.flags |= vk::InstanceCreateFlagBits::eEnumeratePortabilityKHR;
  }
  if (!validation) return request;
  if (!hasLayer(context, kValidationLayer)) {
    throw DeviceUnavailable(std::string("validation asked for, but ") + kValidationLayer +
                            " is not installed (Debian: apt-get install vulkan-validationlayers)");
  }
  request.layers.push_back(kValidationLayer);
  request.extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  request.validationFeatures = hasExtension(context.enumerateInstanceExtensionProperties(std::string(kValidationLayer)),
                                            VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
  if (request.validationFeatures) request.extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
  return request;
}

vk::raii::Instance createInstance(const vk::raii::Context& context, const ContextOptions& options,
                                  ValidationCounter& counter) {
  const bool validation = options.validation;
  const InstanceRequest request = instanceRequest(context, options);
  const vk::ApplicationInfo app{.pApplicationName = "raytracer", .apiVersion = kApiVersion};
  vk::InstanceCreateInfo info{.flags = request.flags,
                              .pApplicationInfo = &app,
                              .enabledLayerCount = static_cast<std::uint32_t>(request.layers.size()),
                              .ppEnabledLayerNames = request.layers.data(),
                              .enabledExtensionCount = static_cast<std::uint32_t>(request.extensions.size()),
                              .ppEnabledExtensionNames = request.extensions.data()};
  // The messenger is chained into the create info too, so that instance
  // creation and destruction are checked as well.
  vk::DebugUtilsMessengerCreateInfoEXT messenger = messengerCreateInfo(counter);
  constexpr std::array kFeatures{vk::ValidationFeatureEnableEXT::eSynchronizationValidation};
  vk::ValidationFeaturesEXT features{.enabledValidationFeatureCount = kFeatures.size(),
                                     .pEnabledValidationFeatures = kFeatures.data()};
  if (validation) info.pNext = &messenger;
  if (request.validationFeatures) messenger.pNext = &features;
  try {
    return vk::raii::Instance(context, info);
  } catch (const vk::SystemError& e) {
    throw DeviceUnavailable(std::string("cannot create a Vulkan instance (") + e.what() +
                            "): no usable Vulkan driver was found (Debian: mesa-vulkan-drivers provides lavapipe)" +
                            "\nVulkan devices found:\n  (none)" + loaderEnvironmentNote());
  }
}

DeviceType deviceType(vk::PhysicalDeviceType type) {
  switch (type) {
    case vk::PhysicalDeviceType::eDiscreteGpu: return DeviceType::discrete;
    case vk::PhysicalDeviceType::eIntegratedGpu: return DeviceType::integrated;
    case vk::PhysicalDeviceType::eVirtualGpu: return DeviceType::virtual_gpu;
    case vk::PhysicalDeviceType::eCpu: return DeviceType::cpu;
    default: return DeviceType::other;
  }
}

// The first compute-capable family; among them one with timestamps, so gpu_ms can be measured.
std::optional<std::uint32_t> computeQueueFamily(const std::vector<vk::QueueFamilyProperties>& families) {
  std::optional<std::uint32_t> any;
  for (std::uint32_t i = 0; i < families.size(); ++i) {
    if (!(families[i].queueFlags & vk::QueueFlagBits::eCompute)) continue;
    if (families[i].timestampValidBits > 0) return i;
    if (!any) any = i;
  }
  return any;
}

PhysicalDeviceChoice describe(vk::raii::PhysicalDevice physical, std::uint32_t index) {
  const vk::PhysicalDeviceProperties props = physical.getProperties();
  DeviceInfo info{.index = index,
                  .name = props.deviceName.data(),
                  .type = deviceType(props.deviceType),
                  .vendorId = props.vendorID,
                  .deviceId = props.deviceID,
                  .driverVersion = decodeDriverVersion(props.vendorID, props.driverVersion),
                  .driverVersionRaw = props.driverVersion,
                  .apiVersion = versionString(props.apiVersion),
                  .timestampPeriodNs = props.limits.timestampPeriod};
  if (props.apiVersion < kApiVersion) {
    info.unsuitableReason = "Vulkan " + info.apiVersion + " < 1.2";
  } else {
    // Core in 1.2: only asked for where it exists.
    const auto chain = physical.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceDriverProperties>();
    const auto& driver = chain.get<vk::PhysicalDeviceDriverProperties>();
    info.driverName = driver.driverName.data();
    info.driverInfo = driver.driverInfo.data();
  }
  const auto families = physical.getQueueFamilyProperties();
  const auto family = computeQueueFamily(families);
  if (family) {
    info.timestampValidBits = families[*family].timestampValidBits;
  } else if (info.suitable()) {
    info.unsuitableReason = "no compute queue";
  }
  return {std::move(physical), std::move(info), family.value_or(0)};
}

// The extensions the ray-tracing pipeline renderer needs (VK_KHR_deferred_host_operations:
// required by the acceleration structure extension); the hit reorder's when asked for.
std::vector<const char*> rayTracingExtensions(const ContextOptions& options) {
  std::vector<const char*> names;
  if (!options.rayTracing) return names;
  names = {VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME, VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME,
           VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME};
  if (options.invocationReorder) names.push_back(VK_NV_RAY_TRACING_INVOCATION_REORDER_EXTENSION_NAME);
  return names;
}

// Refuses `physical` where it lacks one of them, naming what it lacks and what would do.
void requireRayTracing(const vk::raii::PhysicalDevice& physical, const DeviceInfo& described,
                       const ContextOptions& options) {
  const auto available = physical.enumerateDeviceExtensionProperties();
  std::string missing;
  bool pipelineMissing = false;
  for (const char* name : rayTracingExtensions(options)) {
    if (hasExtension(available, name)) continue;
    missing += (missing.empty() ? "" : ", ") + std::string(name);
    pipelineMissing = pipelineMissing || name != std::string_view(VK_NV_RAY_TRACING_INVOCATION_REORDER_EXTENSION_NAME);
  }
  if (missing.empty()) return;
  const std::string device =
      "device " + std::to_string(described.index) + " (" + described.name + ", " + described.driverInfo + ")";
  if (pipelineMissing) {
    throw DeviceUnavailable(device + " cannot run the ray-tracing pipeline renderer (--gpu-rt): it offers no " +
                            missing +
                            ". Mesa's lavapipe has them from Mesa 25 (Debian 13), not Debian 12's 22.3; "
                            "--gpu runs the compute renderer on any Vulkan device");
  }
  throw DeviceUnavailable(device + " cannot reorder hits (--gpu-rt-reorder hit): it offers no " + missing +
                          ", which NVIDIA's drivers have; --gpu-rt-reorder none runs without it");
}

// Refuses `physical` where the run needs shaderFloat16 and it lacks it.
void requireShaderFloat16(const vk::raii::PhysicalDevice& physical, const DeviceInfo& described) {
  const auto features = physical.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDeviceVulkan12Features>();
  if (features.get<vk::PhysicalDeviceVulkan12Features>().shaderFloat16) return;
  throw FeatureUnavailable("device " + std::to_string(described.index) + " (" + described.name + ", " +
                           described.driverInfo +
                           ") offers no shaderFloat16: the GPU renderer cannot compute in half precision "
                           "(--precision f16) there; --precision f32 runs on any Vulkan device");
}

// Whether pipelines may opt out of bounds-checked storage-buffer access
// (VK_EXT_pipeline_robustness). NVIDIA's driver guards every storage-buffer
// load with a bounds test unless a pipeline opts out; see Device::pipelineRobustness.
bool offersPipelineRobustness(const vk::raii::PhysicalDevice& physical) {
  if (!hasExtension(physical.enumerateDeviceExtensionProperties(), VK_EXT_PIPELINE_ROBUSTNESS_EXTENSION_NAME)) {
    return false;
  }
  const auto features =
      physical.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDevicePipelineRobustnessFeaturesEXT>();
  return features.get<vk::PhysicalDevicePipelineRobustnessFeaturesEXT>().pipelineRobustness == VK_TRUE;
}

vk::raii::Device createLogicalDevice(const vk::raii::PhysicalDevice& physical, std::uint32_t queueFamily,
                                     const DeviceInfo& described, const ContextOptions& options,
                                     bool pipelineRobustness) {
  const bool swapchain = options.presents();
  const float priority = 1.0f;
  const vk::DeviceQueueCreateInfo queue{
      .queueFamilyIndex = queueFamily, .queueCount = 1, .pQueuePriorities = &priority};
  std::vector<const char*> extensions;
  // A portability implementation (MoltenVK) must have its subset enabled.
  if (hasExtension(physical.enumerateDeviceExtensionProperties(), "VK_KHR_portability_subset")) {
    extensions.push_back("VK_KHR_portability_subset");
  }
  if (swapchain) {
    if (!hasExtension(physical.enumerateDeviceExtensionProperties(), VK_KHR_SWAPCHAIN_EXTENSION_NAME)) {
      throw DeviceUnavailable("device " + std::to_string(described.index) + " (" + described.name + ") has no " +
                              VK_KHR_SWAPCHAIN_EXTENSION_NAME + ": it cannot present to a window");
    }
    extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  }
  if (options.shaderFloat16) requireShaderFloat16(physical, described);
  if (options.rayTracing) {
    requireRayTracing(physical, described, options);
    // One push_back each: GCC 14 inlines a range insert into a memmove that
    // its -Wstringop-overflow misreads as writing past the vector.
    for (const char* name : rayTracingExtensions(options)) extensions.push_back(name);
  }
  if (pipelineRobustness) extensions.push_back(VK_EXT_PIPELINE_ROBUSTNESS_EXTENSION_NAME);
  vk::StructureChain<
      vk::DeviceCreateInfo, vk::PhysicalDeviceVulkan12Features, vk::PhysicalDeviceAccelerationStructureFeaturesKHR,
      vk::PhysicalDeviceRayTracingPipelineFeaturesKHR, vk::PhysicalDeviceRayTracingInvocationReorderFeaturesNV,
      vk::PhysicalDevicePipelineRobustnessFeaturesEXT>
      chain{vk::DeviceCreateInfo{.queueCreateInfoCount = 1,
                                 .pQueueCreateInfos = &queue,
                                 .enabledExtensionCount = static_cast<std::uint32_t>(extensions.size()),
                                 .ppEnabledExtensionNames = extensions.data()},
            vk::PhysicalDeviceVulkan12Features{.shaderFloat16 = options.shaderFloat16 ? VK_TRUE : VK_FALSE,
                                               .bufferDeviceAddress = options.rayTracing ? VK_TRUE : VK_FALSE},
            vk::PhysicalDeviceAccelerationStructureFeaturesKHR{.accelerationStructure = VK_TRUE},
            vk::PhysicalDeviceRayTracingPipelineFeaturesKHR{.rayTracingPipeline = VK_TRUE},
            vk::PhysicalDeviceRayTracingInvocationReorderFeaturesNV{.rayTracingInvocationReorder = VK_TRUE},
            vk::PhysicalDevicePipelineRobustnessFeaturesEXT{.pipelineRobustness = VK_TRUE}};
  // Without ray tracing or half precision the device is created as before: no features chained.
  if (!options.rayTracing && !options.shaderFloat16) chain.unlink<vk::PhysicalDeviceVulkan12Features>();
  if (!options.rayTracing) {
    chain.unlink<vk::PhysicalDeviceAccelerationStructureFeaturesKHR>();
    chain.unlink<vk::PhysicalDeviceRayTracingPipelineFeaturesKHR>();
  }
  if (!options.invocationReorder) chain.unlink<vk::PhysicalDeviceRayTracingInvocationReorderFeaturesNV>();
  if (!pipelineRobustness) chain.unlink<vk::PhysicalDevicePipelineRobustnessFeaturesEXT>();
  return vk::raii::Device(physical, chain.get<vk::DeviceCreateInfo>());
}

}  // namespace

// Driver-selection variables the loader honours: named in "no device"
// errors, since a stray one is the usual reason a device is missing.
constexpr std::array kLoaderEnvironment{"VK_DRIVER_FILES", "VK_ICD_FILENAMES", "VK_ADD_DRIVER_FILES",
                                        "VK_LOADER_DRIVERS_SELECT", "VK_LOADER_DRIVERS_DISABLE"};

std::string loaderEnvironmentNote() {
  std::string text;
  for (const char* name : kLoaderEnvironment) {
    if (const char* value = std::getenv(name)) text += std::string("\n  ") + name + "=" + value;
  }
  return text.empty() ? "" : "\nLoader environment:" + text;
}

// Loader ======================================================================

void LoaderLibrary::Closer::operator()(void* handle) const { dlclose(handle); }

LoaderLibrary::LoaderLibrary(const std::string& name) : handle_(dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL)) {
  if (!handle_) {
    const char* why = dlerror();
    throw DeviceUnavailable("no Vulkan loader: cannot open " + name + " (" + (why ? why : "unknown reason") +
                            "). Install it (Debian: apt-get install libvulkan1 mesa-vulkan-drivers).");
  }
  getInstanceProcAddr_ = reinterpret_cast<PFN_vkGetInstanceProcAddr>(dlsym(handle_.get(), "vkGetInstanceProcAddr"));
  if (!getInstanceProcAddr_) throw DeviceUnavailable(name + " is not a Vulkan loader: no vkGetInstanceProcAddr");
}

// Instance ====================================================================

Instance::Instance(const ContextOptions& options)
    : validation_(options.validation),
      loader_(options.loaderLibrary),
      context_(loader_.getInstanceProcAddr()),
      instance_(createInstance(context_, options, *counter_)) {
  if (validation_) messenger_ = vk::raii::DebugUtilsMessengerEXT(instance_, messengerCreateInfo(*counter_));
}

std::vector<PhysicalDeviceChoice> describePhysicalDevices(const Instance& instance) {
  std::vector<PhysicalDeviceChoice> devices;
  std::uint32_t index = 0;
  for (vk::raii::PhysicalDevice& physical : instance.get().enumeratePhysicalDevices()) {
    devices.push_back(describe(std::move(physical), index++));
  }
  return devices;
}

// Device ======================================================================

Device::Device(const ContextOptions& options) : instance_(options) {
  std::vector<PhysicalDeviceChoice> candidates = describePhysicalDevices(instance_);
  std::vector<DeviceInfo> infos;
  for (const auto& c : candidates) infos.push_back(c.info);
  if (infos.empty()) {
    throw DeviceUnavailable(
        "the Vulkan loader reports no physical device (Debian: mesa-vulkan-drivers provides "
        "lavapipe)" +
        loaderEnvironmentNote());
  }
  PhysicalDeviceChoice& chosen = candidates[chooseDevice(infos, options.deviceSelector)];
  info_ = chosen.info;
  physical_ = std::move(chosen.physical);
  queueFamily_ = chosen.queueFamily;
  memory_ = physical_.getMemoryProperties();
  pipelineRobustness_ = offersPipelineRobustness(physical_);
  device_ = createLogicalDevice(physical_, queueFamily_, info_, options, pipelineRobustness_);
  queue_ = vk::raii::Queue(device_, queueFamily_, 0);
  shaderFloat16_ = options.shaderFloat16;  // createLogicalDevice refused a device without it
}

std::uint32_t Device::memoryTypeIndex(std::uint32_t typeBits, vk::MemoryPropertyFlags required,
                                      vk::MemoryPropertyFlags preferred) const {
  for (const vk::MemoryPropertyFlags wanted : {required | preferred, required}) {
    for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
      const bool allowed = (typeBits >> i) & 1u;
      if (allowed && (memory_.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
    }
  }
  throw DeviceError("no Vulkan memory type with properties " + vk::to_string(required));
}

vk::MemoryPropertyFlags Device::memoryTypeProperties(std::uint32_t typeIndex) const {
  return memory_.memoryTypes[typeIndex].propertyFlags;
}

}  // namespace rt::gpu
