#!/usr/bin/env bash
# FEMorph's main job on a fresh Debian 12 machine: installs what is needed,
# builds the plugin (Release, into build/) and changes the boss height of the
# default part, Data/boss_block.vtu, 15 -> 20 mm on its mesh (FEMorph Segment,
# then FEMorph Deform with its built-in improvement), checks it (FEMorph Mesh
# Quality), writes out/boss_block_deformed.vtu and out/boss_block_deform.png
# (before and after) and prints the summary, with the time Gmsh takes to
# re-mesh the changed CAD part beside. Arguments go to the demo
# (Testing/Python/demo_deform.py), e.g. --type CylinderRadius
# --control-point 47 30 28 --target 14.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

bash Testing/Scripts/install_dependencies.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DFEMORPH_BUILD_PLUGIN=ON
cmake --build build -j"$(nproc)" --target FEMorph

# The picture needs X: a virtual one. -noreset keeps Xvfb from resetting
# between pvbatch's connections (otherwise ~1 run in 8 fails).
xvfb-run -a -s "-noreset -screen 0 1280x1024x24" \
  pvbatch Testing/Python/demo_deform.py --build-dir build --output-dir out "$@"
