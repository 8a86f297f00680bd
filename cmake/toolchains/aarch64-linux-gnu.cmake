# Cross-compiling for aarch64 Linux on an x86-64 Debian 12 or 13 machine
# (`cmake --preset aarch64`): Debian's cross compiler g++-aarch64-linux-gnu
# and the arm64 builds of the libraries, installed beside the amd64 ones
# through multiarch (`scripts/setup-debian --cross aarch64`). ctest and the
# scripts run the binaries under qemu-user (CMAKE_CROSSCOMPILING_EMULATOR).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

# Multiarch: the arm64 libraries live in /usr/lib/aarch64-linux-gnu and
# their CMake and pkg-config files beside them; headers without an
# architecture (glm, nlohmann-json, CLI11) are shared with the host.
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig")

# Plain qemu-aarch64, without -L: the arm64 libc and loader are installed in
# the host's own /lib (multiarch), and the cross toolchain's sysroot under
# /usr/aarch64-linux-gnu hangs every run with more than one oneTBB thread.
# QEMU_CPU (the environment) picks the emulated CPU: cortex-a72 for NEON
# without SVE, max for SVE (qemu's default).
find_program(RT_QEMU_AARCH64 qemu-aarch64 REQUIRED)
set(CMAKE_CROSSCOMPILING_EMULATOR ${RT_QEMU_AARCH64})
