#!/usr/bin/env bash
# FEMorph's main job on a fresh Debian 12 machine: installs what is needed,
# builds the plugin (Release, into build/) and runs FEMorph Mesh Quality on
# the default part, Data/boss_block.vtu. Writes out/boss_block_quality.vtu and
# out/boss_block_stretch.png and prints the quality summary.
# Arguments go to the demo: bash Testing/Scripts/demo.sh path/to/part.vtu
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

bash Testing/Scripts/install_dependencies.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DFEMORPH_BUILD_PLUGIN=ON
cmake --build build -j"$(nproc)" --target FEMorph

# The picture needs X: a virtual one. -noreset keeps Xvfb from resetting
# between pvbatch's connections (otherwise ~1 run in 8 fails).
xvfb-run -a -s "-noreset -screen 0 1280x1024x24" \
  pvbatch Testing/Python/demo_mesh_quality.py --build-dir build --output-dir out "$@"
