#!/usr/bin/env bash
# Installs every Debian package the project needs, once. Idempotent: does nothing when all
# packages are present. Each package is listed here and nowhere else.
set -euo pipefail
PACKAGES=(
  build-essential cmake pkg-config ninja-build
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev   # CGAL and its number types
  libeigen3-dev                                      # dense/sparse algebra
  libgmsh-dev gmsh                                   # CAD fit and surface meshing
  libassimp-dev                                      # reading scan formats
  nlohmann-json3-dev                                 # JSON reports and decks
  libgtest-dev libgmock-dev libbenchmark-dev         # tests and benchmarks
  python3 python3-meshio python3-numpy python3-matplotlib python3-h5py  # conversion, plots
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "install-deps: installing ${missing[*]}" >&2
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
