# Every dependency comes from the system. A missing one stops the configure
# step with the Debian package that provides it (scripts/setup-debian
# installs them all).

find_package(PkgConfig QUIET)

macro(rt_require_package name debian_package)
  find_package(${name} ${ARGN} QUIET)
  if(NOT ${name}_FOUND)
    message(FATAL_ERROR
      "Missing dependency '${name}'. On Debian/Ubuntu: apt-get install ${debian_package}"
      " (or run scripts/setup-debian as root).")
  endif()
endmacro()

macro(rt_require_pkg_config prefix module debian_package)
  if(NOT PKG_CONFIG_FOUND)
    message(FATAL_ERROR "Missing pkg-config. On Debian/Ubuntu: apt-get install pkg-config")
  endif()
  pkg_check_modules(${prefix} QUIET IMPORTED_TARGET ${module})
  if(NOT ${prefix}_FOUND)
    message(FATAL_ERROR
      "Missing dependency '${module}' (pkg-config). On Debian/Ubuntu: apt-get install ${debian_package}"
      " (or run scripts/setup-debian as root).")
  endif()
endmacro()

# A program used at build time (found once, cached in `var`).
macro(rt_require_program var program debian_package)
  find_program(${var} ${program})
  if(NOT ${var})
    message(FATAL_ERROR
      "Missing program '${program}'. On Debian/Ubuntu: apt-get install ${debian_package}"
      " (or run scripts/setup-debian as root).")
  endif()
endmacro()

rt_require_package(Threads libc6-dev)
rt_require_package(glm libglm-dev)
rt_require_package(nlohmann_json nlohmann-json3-dev)
# The scene loader's parser (On-Demand API; Debian 12 ships 3.0.1).
# Debian 12's libsimdjson-dev cannot be installed for a second architecture
# (Multi-Arch: no), so the aarch64 cross build there has the arm64 library
# (libsimdjson14:arm64, dependencies.toml) without its CMake files: the
# target is then made from that library and the host's headers, which are
# the same for every architecture.
find_package(simdjson QUIET)
if(NOT simdjson_FOUND AND CMAKE_CROSSCOMPILING)
  find_library(RT_SIMDJSON_LIBRARY NAMES simdjson libsimdjson.so.14)
  find_path(RT_SIMDJSON_INCLUDE simdjson.h)
  if(RT_SIMDJSON_LIBRARY AND RT_SIMDJSON_INCLUDE)
    add_library(simdjson::simdjson UNKNOWN IMPORTED)
    set_target_properties(simdjson::simdjson PROPERTIES IMPORTED_LOCATION "${RT_SIMDJSON_LIBRARY}"
                                                        INTERFACE_INCLUDE_DIRECTORIES "${RT_SIMDJSON_INCLUDE}")
  endif()
endif()
if(NOT TARGET simdjson::simdjson)
  rt_require_package(simdjson libsimdjson-dev)
endif()
rt_require_package(CLI11 libcli11-dev)
rt_require_pkg_config(STB stb libstb-dev)
# Threads of the simd_tbb and tbb_only renderers.
rt_require_package(TBB libtbb-dev)
# SIMD packets with run-time dispatch; 1.0.x API (Debian 12 ships 1.0.3).
rt_require_package(hwy libhwy-dev)
# Vulkan: only the headers are used at build time; the loader is opened at
# run time (src/gpu/vulkan/device.cpp), so the binary starts without it.
rt_require_package(Vulkan libvulkan-dev)
rt_require_program(RT_GLSLANG_VALIDATOR glslangValidator glslang-tools)
execute_process(COMMAND "${RT_GLSLANG_VALIDATOR}" --version OUTPUT_VARIABLE _glslang_version_text ERROR_QUIET)
string(REGEX MATCH "Glslang Version: [0-9]+:([0-9.]+)" _glslang_match "${_glslang_version_text}")
set(RT_GLSLANG_VERSION "${CMAKE_MATCH_1}")

if(RT_BUILD_TESTS)
  rt_require_package(GTest libgtest-dev)
endif()

# An optional feature over one package: option OPTION is on by default
# where the package is found; asked for and missing stops the configure
# step naming the Debian package. Off, the feature stays in the schema and
# answers "not built" (exit 2). `versions` is one version or a list tried
# in order (the first found wins).
macro(rt_optional_feature option package versions debian what)
  foreach(_rt_version IN ITEMS ${versions})
    find_package(${package} ${_rt_version} QUIET)
    if(${package}_FOUND)
      break()
    endif()
  endforeach()
  option(${option} "Build ${what}" ${${package}_FOUND})
  if(${option} AND NOT ${package}_FOUND)
    string(REPLACE ";" " or " _rt_versions_text "${versions}")
    message(FATAL_ERROR
      "${option} is ON but ${package} ${_rt_versions_text} was not found. On Debian/Ubuntu: apt-get install ${debian}"
      " (or run scripts/setup-debian as root), or configure with -D${option}=OFF.")
  endif()
endmacro()

# Embree 4 (Debian 13, nixpkgs), else Embree 3 (Debian 12), for the Embree
# reference renderer (--embree). Embree's config-version files accept only
# their own major version, so each major is asked for by itself. The code
# gets the major found as RT_EMBREE_MAJOR (src/render/embree/embree_api.h).
rt_optional_feature(RT_EMBREE embree "4;3" libembree-dev "the Embree reference renderer (--embree)")
if(RT_EMBREE)
  set(RT_EMBREE_MAJOR "${embree_VERSION_MAJOR}")
  message(STATUS "Embree ${embree_VERSION} (RT_EMBREE_MAJOR=${RT_EMBREE_MAJOR})")
endif()
# GLFW 3, for the live window (--window); CI and the Nix package build it,
# and without it the binary keeps today's dependencies.
rt_optional_feature(RT_WINDOW glfw3 3.3 libglfw3-dev "the live window (--window): GLFW + a Vulkan swapchain")

# Versions recorded in every run's metadata (the ones this binary was built against).
set(RT_LIBRARY_VERSIONS
  "glm=${glm_VERSION}"
  "nlohmann_json=${nlohmann_json_VERSION}"
  "simdjson=${simdjson_VERSION}"
  "CLI11=${CLI11_VERSION}"
  "stb=${STB_VERSION}"
  "TBB=${TBB_VERSION}"
  "hwy=${hwy_VERSION}"
  "vulkan_headers=${Vulkan_VERSION}"
  "glslang=${RT_GLSLANG_VERSION}")
if(RT_EMBREE)
  list(APPEND RT_LIBRARY_VERSIONS "embree=${embree_VERSION}")
endif()
if(RT_WINDOW)
  list(APPEND RT_LIBRARY_VERSIONS "glfw=${glfw3_VERSION}")
endif()
