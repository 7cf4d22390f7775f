#!/usr/bin/env bash
# Idempotent set-up for a fresh Debian machine: installs the Debian packages imuconv needs
# (only the missing ones) and configures the build in ./build (Release).
# Usage: ./setup.sh [extra cmake arguments]
set -euo pipefail
cd "$(dirname "$0")"

packages=(g++ cmake make pkg-config libeigen3-dev libboost-dev nlohmann-json3-dev libgtest-dev
          libbenchmark-dev libcli11-dev python3 python3-jsonschema)
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
