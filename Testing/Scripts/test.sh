#!/usr/bin/env bash
# Every FEMorph test on a fresh Debian 12 machine: installs what is needed,
# builds everything (Release, with the ParaView plugin, into build/) and runs
# ctest: core and filter unit tests (GoogleTest) and the plugin tests
# (pvbatch/pvpython, the demo under Xvfb) and the malformed-input corpus
# (Testing/Corpus). Then builds the test executables again with
# AddressSanitizer and UndefinedBehaviorSanitizer (build-asan/: the core, the
# filters module and their tests, the corpus; not the ParaView plugin) and
# runs them, all but the Python and Install tests (pvbatch and pvpython are
# not instrumented). Exits
# non-zero when a build or any test fails.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
jobs=$(nproc)

bash Testing/Scripts/install_dependencies.sh

status=0
echo "=== Release build with the plugin (build/)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release \
  -DFEMORPH_BUILD_PLUGIN=ON -DFEMORPH_BUILD_TESTING=ON -DFEMORPH_BUILD_BENCHMARKS=ON \
  -DFEMORPH_SANITIZE=OFF
cmake --build build -j"$jobs"
(cd build && ctest --output-on-failure -j"$jobs" --timeout 1800) || status=1
# Python.GUI's screenshots of every filter in the ParaView GUI (artifacts).
if ls build/Testing/Python/gui/*.png >/dev/null 2>&1; then
  echo "=== GUI screenshots: $(pwd)/build/Testing/Python/gui/"
fi

echo "=== Core, filter and corpus tests with AddressSanitizer + UBSan (build-asan/)"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DFEMORPH_BUILD_PLUGIN=ON -DFEMORPH_BUILD_TESTING=ON -DFEMORPH_BUILD_BENCHMARKS=OFF \
  -DFEMORPH_SANITIZE=ON
# The test executables only (Testing/Corpus/CMakeLists.txt): the ParaView
# plugin library is not built, and the tests that load it into pvbatch or
# pvpython (labels Python and Install) are left out: those are not
# instrumented; so is the CalculiX harness (label FEA), which has no C++.
cmake --build build-asan -j"$jobs" --target femorph_tests_without_plugin
(cd build-asan && ctest --output-on-failure -j"$jobs" --timeout 3600 -LE "Python|Install|FEA") || status=1

if [[ $status -ne 0 ]]; then
  echo "=== FAILED: see the ctest output above"
else
  echo "=== all tests passed"
fi
exit $status
