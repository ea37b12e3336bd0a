#!/usr/bin/env bash
# Installs every Debian 12 package FEMorph needs to build (core, filters,
# ParaView plugin with its XML documentation), test, run the demo and the
# benchmarks, and regenerate Data/. Uses sudo when not root. Skips apt when
# everything is already installed (FEMORPH_FORCE_INSTALL=1 to run it anyway).
set -euo pipefail

packages=(
  # Build tools.
  build-essential cmake
  # The core: Eigen and TetGen (library and the tetgen program).
  libeigen3-dev libtet1.5-dev tetgen
  # ParaView 5.11 SDK with its VTK; python3-paraview holds part of the CMake
  # package (vtkmodules, pvpython, hierarchy files); MPI and double-conversion
  # are needed to configure against it.
  paraview-dev python3-paraview libopenmpi-dev libdouble-conversion-dev
  # The plugin's XML documentation: Qt's xmlpatterns, Qt5Help and qhelpgenerator.
  qtxmlpatterns5-dev-tools qttools5-dev qttools5-dev-tools qhelpgenerator-qt5
  # Tests and benchmarks; CGAL (header-only, with GMP and MPFR) is the peer of
  # the segmentation benchmark only.
  libgtest-dev libbenchmark-dev python3-numpy libcgal-dev libgmp-dev libmpfr-dev
  # Pictures from pvbatch need an X server (Debian's ParaView has no EGL/OSMesa).
  xvfb xauth
  # Python.Distributed: mpiexec (ParaView's MPI is OpenMPI); Python.GUI: the
  # ParaView GUI itself.
  openmpi-bin paraview
  # Data/generate_parts.py: CAD parts through Gmsh's OpenCASCADE kernel.
  python3-gmsh gmsh
  # Testing/FEA: the CalculiX solver (the FEA.Harness test is skipped without it).
  calculix-ccx
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [[ ${#missing[@]} -eq 0 && "${FEMORPH_FORCE_INSTALL:-0}" != 1 ]]; then
  echo "install_dependencies: all ${#packages[@]} packages are installed"
  exit 0
fi

sudo=()
if [[ $(id -u) -ne 0 ]]; then
  sudo=(sudo)
fi
echo "install_dependencies: installing ${missing[*]:-${packages[*]}}"
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update
"${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y "${packages[@]}"
