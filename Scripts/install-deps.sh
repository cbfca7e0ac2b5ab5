#!/usr/bin/env bash
# Installs every Debian package HairDynamics needs to build, test and run its demo.
# Idempotent: when every package is already present it returns in about a second
# without touching the network.
set -euo pipefail

PACKAGES=(
  # compilers and build tools
  build-essential cmake git clang-format clang-tidy
  # ParaView 5.11 with its own VTK 9.1 (never libvtk9-dev next to it)
  paraview paraview-dev python3-paraview
  # what find_package(ParaView) re-finds (see shared/design/toolchain-notes.md)
  qtbase5-dev qttools5-dev libqt5svg5-dev libqt5opengl5-dev qtxmlpatterns5-dev-tools
  libutfcpp-dev libdouble-conversion-dev zlib1g-dev libtiff-dev libtheora-dev
  python3-dev libpng-dev libgl-dev libnetcdf-dev mpi-default-dev libxml2-dev liblzma-dev
  liblz4-dev libjpeg-dev libhdf5-openmpi-dev libglew-dev libgl2ps-dev libgdal-dev
  libavcodec-dev libavformat-dev libswscale-dev libavutil-dev libfreetype-dev
  libexpat1-dev libboost-dev libx11-dev
  # HairDynamics' own libraries
  libeigen3-dev libcgal-dev libhdf5-dev libgtest-dev libgmock-dev libbenchmark-dev
  # the fuzz target (Scripts/fuzz.sh): clang with libFuzzer and its OpenMP runtime
  clang libclang-rt-14-dev libomp-14-dev
  # runtime of tests, demo and studies
  python3-numpy python3-matplotlib python3-h5py python3-mpi4py xvfb xauth mpi-default-bin
  # the GUI tests: drive ParaView's menu, take screenshots, compare one with its baseline
  xdotool imagemagick python3-pil
  # the bundled body's source (Data/make_body.sh regenerates Data/ from it)
  assimp-utils assimp-testmodels
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${#missing[@]} Debian packages: ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: these packages are missing and installing them needs root" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
