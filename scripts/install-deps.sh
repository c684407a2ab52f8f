#!/usr/bin/env bash
# Installs everything Weft's build and tests need on Debian 12 (bookworm), as root or through sudo.
# Idempotent: when every package is already installed it returns at once without touching apt.
#   bash scripts/install-deps.sh            # WEFT_FORCE_APT=1 to run apt-get even so
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config  # toolchain
  libglm-dev libembree-dev                      # runtime: maths, BVH queries
  doctest-dev libcgal-dev                       # tests (CGAL meshes the irregular disc; weft-bake later)
  libcli11-dev nlohmann-json3-dev libxxhash-dev # tools: command lines, JSON, asset hashing
  clang libclang-rt-14-dev                      # fuzzing (clang -fsanitize=fuzzer)
  libbullet-dev gnuplot-nox jq                  # weft-bench sweep: the Bullet peer, the Pareto plot; bench-baseline.sh
  libtinyobjloader-dev libtinygltf-dev          # lib/body: body meshes from OBJ and glTF
  libmeshoptimizer-dev                          # weft-bench body --simplify: simplified collision hulls
  libepoxy-dev libegl-dev libegl-mesa0          # tools/render: OpenGL loader, EGL (surfaceless)
  libgl1-mesa-dri libstb-dev ffmpeg             # llvmpipe, PNG writing, weft-sim --gif/--mp4, figures
  libglfw3-dev libimgui-dev fonts-dejavu-core   # samples/viewer: window, panel, the panel's font
  xvfb xauth                                    # the viewer's test: a real window on a virtual display
)
# The glTF test validates weft-sim --gltf with Khronos' validator (npm gltf-validator, installed by
# the test itself into build/): it needs Node.js and npm. A machine that has them (from any source)
# keeps its own; Debian's packages otherwise.
if ! command -v npm >/dev/null || ! command -v node >/dev/null; then
  packages+=(nodejs npm)
fi

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2>/dev/null || true)
  [[ "$status" == ii* ]] || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 && -z "${WEFT_FORCE_APT:-}" ]]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: run as root (or install sudo)" >&2; exit 1; }
  sudo=(sudo)
fi

echo "install-deps: installing ${missing[*]:-(forced: all present)}"
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
  -o Dpkg::Use-Pty=0 "${packages[@]}" >/dev/null
echo "install-deps: done"
