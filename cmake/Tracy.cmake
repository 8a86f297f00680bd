# Tracy instrumentation. RT_TRACY=OFF (the default, and the benchmark
# build): no Tracy code at all, the zone macros expand to nothing.
# RT_TRACY=ON: Tracy's C++ client is built from source as one static
# library. Its sources come from RT_TRACY_CLIENT_DIR (the directory holding
# TracyClient.cpp, e.g. nixpkgs' tracy source under Nix) or, when that is
# empty, from scripts/fetch-tracy-client (Tracy 0.14.1 via cargo).

option(RT_TRACY "Build with the Tracy profiler client" OFF)
# The environment variable of the same name gives the default (the Nix dev
# shell sets it to nixpkgs' Tracy client).
set(RT_TRACY_CLIENT_DIR "$ENV{RT_TRACY_CLIENT_DIR}" CACHE PATH "Directory holding Tracy's TracyClient.cpp; fetched when empty")

add_library(rt_tracy INTERFACE)
if(NOT RT_TRACY)
  return()
endif()

if(NOT RT_TRACY_CLIENT_DIR)
  execute_process(
    COMMAND "${PROJECT_SOURCE_DIR}/scripts/fetch-tracy-client"
    OUTPUT_VARIABLE fetched ERROR_VARIABLE fetch_error RESULT_VARIABLE fetch_rc
    OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT fetch_rc EQUAL 0)
    message(FATAL_ERROR "RT_TRACY=ON but Tracy's client could not be fetched:\n${fetch_error}")
  endif()
  set(RT_TRACY_CLIENT_DIR "${fetched}" CACHE PATH "Directory holding Tracy's TracyClient.cpp; fetched when empty" FORCE)
endif()
if(NOT EXISTS "${RT_TRACY_CLIENT_DIR}/TracyClient.cpp")
  message(FATAL_ERROR "RT_TRACY_CLIENT_DIR=${RT_TRACY_CLIENT_DIR} holds no TracyClient.cpp")
endif()

file(READ "${RT_TRACY_CLIENT_DIR}/common/TracyVersion.hpp" version_header)
foreach(part Major Minor Patch)
  string(REGEX MATCH "${part} = ([0-9]+)" unused "${version_header}")
  list(APPEND version_parts "${CMAKE_MATCH_1}")
endforeach()
list(JOIN version_parts "." RT_TRACY_VERSION)
message(STATUS "Tracy client ${RT_TRACY_VERSION} from ${RT_TRACY_CLIENT_DIR}")

add_library(TracyClient STATIC "${RT_TRACY_CLIENT_DIR}/TracyClient.cpp")
target_include_directories(TracyClient SYSTEM PUBLIC "${RT_TRACY_CLIENT_DIR}")
target_compile_definitions(TracyClient PUBLIC
  TRACY_ENABLE
  # Never leave loopback: listen on 127.0.0.1 only, no UDP discovery broadcast.
  TRACY_ONLY_LOCALHOST
  TRACY_NO_BROADCAST
  # Collect only while a viewer is connected, so a run nobody watches does
  # not buffer events without bound.
  TRACY_ON_DEMAND)
target_link_libraries(TracyClient PUBLIC Threads::Threads ${CMAKE_DL_LIBS})
set_target_properties(TracyClient PROPERTIES POSITION_INDEPENDENT_CODE ON)
target_link_libraries(rt_tracy INTERFACE TracyClient)
list(APPEND RT_LIBRARY_VERSIONS "tracy_client=${RT_TRACY_VERSION}")
