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

rt_require_package(Threads libc6-dev)
rt_require_package(glm libglm-dev)
rt_require_package(nlohmann_json nlohmann-json3-dev)
rt_require_package(CLI11 libcli11-dev)
rt_require_pkg_config(STB stb libstb-dev)
# Threads of the simd_tbb and tbb_only renderers.
rt_require_package(TBB libtbb-dev)
# SIMD packets with run-time dispatch; 1.0.x API (Debian 12 ships 1.0.3).
rt_require_package(hwy libhwy-dev)

if(RT_BUILD_TESTS)
  rt_require_package(GTest libgtest-dev)
endif()

# Versions recorded in every run's metadata (the ones this binary was built against).
set(RT_LIBRARY_VERSIONS
  "glm=${glm_VERSION}"
  "nlohmann_json=${nlohmann_json_VERSION}"
  "CLI11=${CLI11_VERSION}"
  "stb=${STB_VERSION}"
  "TBB=${TBB_VERSION}"
  "hwy=${hwy_VERSION}")
