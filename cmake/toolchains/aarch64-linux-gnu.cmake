# Cross-compiling imuconv for 64-bit ARM Linux (aarch64: Jetson-class boards, Raspberry Pi 4/5)
# on a Debian x86-64 machine, and running its tests there under user-mode emulation.
#
#   cmake -S . -B build-aarch64 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake \
#         -DIMUCONV_LIBRARY_SUBSET=ON -DIMUCONV_INSTALL=OFF -DIMUCONV_GTEST_SOURCE_DIR=/usr/src/googletest
#
# (what ./setup.sh --aarch64 runs). Debian packages: g++-aarch64-linux-gnu, the cross compiler
# with the target's libc and libstdc++ in /usr/aarch64-linux-gnu; qemu-user, whose
# qemu-aarch64 runs the target's executables here; googletest, GoogleTest's sources, compiled
# for the target in the build tree (tests/CMakeLists.txt). Eigen, Boost and nlohmann_json are
# header-only and architecture-independent: the host's headers in /usr/include serve the target
# as they are. IMUCONV_LIBRARY_SUBSET leaves out what needs a compiled library Debian ships for
# the host only (yaml-cpp, libbenchmark, Python).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

# The target's multiarch name: find_package then looks in /usr/lib/aarch64-linux-gnu, never in
# the host's /usr/lib/x86_64-linux-gnu (whose Boost package file, for one, names x86-64
# libraries; Boost's headers are then found by CMake's FindBoost in /usr/include). No sysroot:
# the cross compiler already searches /usr/aarch64-linux-gnu for libc and libstdc++, and
# /usr/include for the shared headers.
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

# Every executable CMake runs for the target (ctest's tests, gtest_discover_tests' listing of
# each test binary) goes through qemu-aarch64. -L: the dynamic loader, libc and libstdc++ come
# from the cross toolchain's target tree; the build's own libraries through the RUNPATH.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /usr/aarch64-linux-gnu)
