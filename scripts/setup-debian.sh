#!/usr/bin/env bash
# Installs everything OracleMesh needs on a fresh Debian 12 machine (run as root or with sudo).
# Idempotent: packages already present are skipped by apt.
set -euo pipefail
SUDO=""
if [ "$(id -u)" != "0" ]; then SUDO="sudo"; fi
PKGS=(
  # build tools
  cmake ninja-build g++ ccache pkg-config
  # ParaView 5.11 SDK (brings its own VTK 9.2 and the Python vtkmodules)
  paraview paraview-dev python3-paraview
  # paraview-dev needs these but does not pull them in (docs/DESIGN.md, "Build facts")
  libopenmpi-dev libdouble-conversion-dev liblz4-dev liblzma-dev
  # CGAL and its dependencies
  libcgal-dev libboost-dev libeigen3-dev libgmp-dev libmpfr-dev libtbb-dev
  # tests
  libgtest-dev googletest python3-numpy xvfb xauth
  # tests: the sanitizer build (ASan + UBSan) and the libFuzzer harnesses; llvm-14 symbolizes reports
  clang libclang-rt-14-dev llvm-14
  # tests: gmsh's own reader checks the .msh files (gmsh -check); CalculiX solves the .inp files
  gmsh calculix-ccx
  # command line: the report reads the finite-element formats back (meshio; the writers need none), its histogram picture
  python3-meshio python3-matplotlib
  # batch on a Dask cluster (--scheduler, --workers)
  python3-distributed
  # benchmarks: TetGen as a peer of the quality step (Benchmarks/quality_step.py); scipy's k-d tree
  tetgen python3-scipy
)
export DEBIAN_FRONTEND=noninteractive
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all packages present"
fi
