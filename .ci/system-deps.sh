#!/usr/bin/env bash
# System packages the tests need, installed once, quietly (CI runs this as root
# before installing the project). Offscreen OpenGL for the 3D rendering tests:
# EGL with Mesa's software rasterizer (llvmpipe). Without them those tests skip
# with a stated reason; the top-down picture needs no GL.
set -euo pipefail

PACKAGES=(libegl1 libgl1 libgl1-mesa-dri)

missing=()
for p in "${PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

if ! command -v apt-get >/dev/null 2>&1; then
    echo "system-deps: no apt-get; install offscreen OpenGL (EGL or OSMesa) by hand: ${missing[*]}" >&2
    exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1; then SUDO="sudo -n"; else
        echo "system-deps: not root; rendering tests will skip unless ${missing[*]} are installed" >&2
        exit 0
    fi
fi
export DEBIAN_FRONTEND=noninteractive
echo "system-deps: installing ${missing[*]}"
# A failed install is not fatal: the rendering tests then skip and say why.
if ! { $SUDO apt-get update -qq >/dev/null &&
       $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null; }; then
    echo "system-deps: could not install ${missing[*]}; the 3D rendering tests will skip" >&2
fi
