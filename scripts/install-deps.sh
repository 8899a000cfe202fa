#!/usr/bin/env bash
# Installs what building and running translucid needs on Debian/Ubuntu, if it is missing:
# the Vulkan loader and headers, Mesa's drivers (lavapipe runs Vulkan on the CPU when there
# is no GPU), the GLSL compiler, the Khronos validation layer the tests run under, and the C
# toolchain, CMake and pkg-config the tests build the C example and C tests with.
set -euo pipefail

packages=(mesa-vulkan-drivers libvulkan-dev glslc vulkan-validationlayers gcc g++ cmake pkg-config)
missing=()
for p in "${packages[@]}"; do
    dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
    exit 0
fi
if ! command -v apt-get >/dev/null; then
    echo "translucid needs: ${missing[*]} (or your system's equivalents); install them and retry." >&2
    exit 1
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then
    sudo="sudo"
fi
echo "installing ${missing[*]}" >&2
$sudo apt-get update -q
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
