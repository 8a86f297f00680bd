# Run at build time (cmake -P) so the commit and dirty flag describe the
# sources the binary was actually built from, not the last configure.
# Inputs: SOURCE_DIR, OUTPUT, TEMPLATE.

set(RT_GIT_COMMIT "unknown")
set(RT_GIT_DIRTY "false")
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${SOURCE_DIR}" rev-parse HEAD
    OUTPUT_VARIABLE commit RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(rc EQUAL 0)
    set(RT_GIT_COMMIT "${commit}")
    execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${SOURCE_DIR}" status --porcelain --untracked-files=no
      OUTPUT_VARIABLE status RESULT_VARIABLE rc ERROR_QUIET)
    if(rc EQUAL 0 AND NOT status STREQUAL "")
      set(RT_GIT_DIRTY "true")
    endif()
  endif()
endif()
# A source tree without git metadata (the Nix flake builds from a copy in
# the store) may name its commit in the environment instead.
if(RT_GIT_COMMIT STREQUAL "unknown" AND DEFINED ENV{RT_GIT_COMMIT})
  set(RT_GIT_COMMIT "$ENV{RT_GIT_COMMIT}")
  if("$ENV{RT_GIT_DIRTY}" STREQUAL "true")
    set(RT_GIT_DIRTY "true")
  endif()
endif()
configure_file("${TEMPLATE}" "${OUTPUT}" @ONLY)
