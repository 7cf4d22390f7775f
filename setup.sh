#!/usr/bin/env bash
# Idempotent set-up for a fresh Debian machine: installs the Debian packages imuconv needs
# (only the missing ones) and configures the build in ./build (Release).
#
# Usage: ./setup.sh [--sanitizers] [--aarch64] [extra cmake arguments for ./build]
#   --sanitizers  also installs clang and its sanitizer and libFuzzer runtimes and configures
#                 ./build-san: the whole suite under AddressSanitizer and
#                 UndefinedBehaviorSanitizer, plus the libFuzzer targets (tests/fuzz), which
#                 ctest runs for IMUCONV_FUZZ_SECONDS each (30 by default).
#   --aarch64     also installs the aarch64 cross compiler and qemu-user and configures
#                 ./build-aarch64: the library, plugins and the tests of what depends on the
#                 instruction set cross-compiled for 64-bit ARM (GoogleTest built from
#                 Debian's sources), which ctest runs under qemu-aarch64
#                 (cmake/toolchains/aarch64-linux-gnu.cmake; README.md, "Cross-building for aarch64").
set -euo pipefail
cd "$(dirname "$0")"

sanitizers=0
aarch64=0
while [ $# -gt 0 ]; do
  case "$1" in
    --sanitizers) sanitizers=1 ;;
    --aarch64) aarch64=1 ;;
    *) break ;;
  esac
  shift
done

packages=(g++ cmake make pkg-config libeigen3-dev libboost-dev nlohmann-json3-dev libgtest-dev
          libbenchmark-dev libcli11-dev libyaml-cpp-dev python3 python3-jsonschema python3-numpy python3-pytest
          python3-dev pybind11-dev doxygen)
# Ceres Solver 2.1: imuconv::ceres (factors/), the preintegration factors.
packages+=(libceres-dev)
# Headless Chromium renders the HTML reports in a test (tests/report/report_documents.py):
# 122 MB to download, 414 MB installed, about 15 s.
packages+=(chromium)
if [ "$sanitizers" = 1 ]; then
  packages+=(clang libclang-rt-14-dev llvm)
fi
if [ "$aarch64" = 1 ]; then
  packages+=(g++-aarch64-linux-gnu qemu-user googletest)
fi
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup.sh: installing ${missing[*]}"
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" > build-configure.log 2>&1 || { cat build-configure.log; exit 1; }
echo "setup.sh: configured ./build (log: build-configure.log)"

if [ "$sanitizers" = 1 ]; then
  # -O1: the sanitizers' own advice (fast enough to run the suite, keeps stack traces exact).
  # -gline-tables-only: the sanitizers' reports need only function names, files and lines
  # (inlined frames included), not the types and variables of full -g, which cost about a
  # fifth of each unit's compile time here; a debugger session wants its own -g build.
  # No imuconv::ceres here: Debian's libceres is not built with the sanitizers, so they would
  # check only our side of every call into it; the residuals and charts the factors evaluate
  # are the registry's and the plugins', which this tree tests.
  CC=clang CXX=clang++ cmake -S . -B build-san -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" \
    -DIMUCONV_SANITIZE=address,undefined -DIMUCONV_FUZZ=ON -DIMUCONV_CERES=OFF > build-san-configure.log 2>&1 ||
    { cat build-san-configure.log; exit 1; }
  echo "setup.sh: configured ./build-san, AddressSanitizer + UndefinedBehaviorSanitizer + libFuzzer (log: build-san-configure.log)"
fi

if [ "$aarch64" = 1 ]; then
  # No imuconv::ceres: the cross sysroot has no arm64 Ceres (Debian's libceres-dev is the
  # build machine's), and the factors hold no instruction-set dependent code.
  cmake -S . -B build-aarch64 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake \
    -DCMAKE_BUILD_TYPE=Release -DIMUCONV_LIBRARY_SUBSET=ON -DIMUCONV_INSTALL=OFF -DIMUCONV_CERES=OFF \
    -DIMUCONV_GTEST_SOURCE_DIR=/usr/src/googletest > build-aarch64-configure.log 2>&1 ||
    { cat build-aarch64-configure.log; exit 1; }
  echo "setup.sh: configured ./build-aarch64, cross-compiled for aarch64, tests under qemu-aarch64 (log: build-aarch64-configure.log)"
fi
