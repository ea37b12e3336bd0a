#!/usr/bin/env bash
# Runs FEMorph's benchmark programs from a build folder and writes what they
# print into Testing/Benchmarks/RESULTS.md, the one place for benchmark
# figures (code comments and help texts do not carry them).
#
#   bash Testing/Benchmarks/run_benchmarks.sh [--build DIR] [NAME[:ARGS]]...
#
#   --build DIR  the CMake build folder (default: build/ in the repository);
#                the programs are DIR/bin/bench_*.
#   NAME         bench_tet_mesh, bench_segment, bench_improve,
#                bench_tet_to_hex, bench_deform, bench_adapt or bench_threads (default:
#                all seven, in that order);
#                NAME:ARGS passes ARGS, e.g. "bench_improve:--runs=5".
#
# RESULTS.md keeps one section per program between marker comments; a run
# rewrites the sections of the programs it ran and keeps the others, each
# section stating when, on which commit and machine, and with which command
# its figures were made. A program that fails leaves its old section and
# makes the script exit non-zero; its output is in DIR/benchmarks/NAME.log.
# Run on a quiet machine: the figures are wall times.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
build="$repo/build"
results="$here/RESULTS.md"
all=(bench_tet_mesh bench_segment bench_improve bench_tet_to_hex bench_deform bench_adapt bench_threads)

runs=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --build=*) build="${1#--build=}"; shift ;;
    -h|--help) sed -n '2,20p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "unknown option $1 (see --help)" >&2; exit 2 ;;
    *) runs+=("$1"); shift ;;
  esac
done
[[ ${#runs[@]} -gt 0 ]] || runs=("${all[@]}")
build="$(cd "$build" && pwd)"

describe() {
  case "$1" in
    bench_tet_mesh) echo "Core mesh: adjacency build, quality passes and random local operations on a jittered cube of about 1M tets, against one plain pass over the arrays." ;;
    bench_segment) echo "FEMorph Segment: per-step times (thesis Table 2.9 layout) on the Data/ parts and a fine part of about 200,000 boundary triangles, with CGAL's Efficient RANSAC as the peer. The first run makes the fine part with Gmsh (build/bench-data/, minutes)." ;;
    bench_improve) echo "FEMorph Improve: case (b), boss_block at about 528,000 tets with its boss stretched x1.6 and x3, the phased loop and Poor Elements Only against TetGen's and Gmsh's optimizers; then a uniform BCC reference stretched x3. The first run makes the 528k-tet part with Gmsh." ;;
    bench_tet_to_hex) echo "FEMorph Tet To Hex: a jittered grid of about 1M tets, the quad-angle sweep of thesis Table 4.3, and Gmsh's 3D recombination as the peer." ;;
    bench_adapt) echo "FEMorph Adapt's core (thesis chapter 3): the case of thesis 3.7.2 (a 3x5x1-cube object in 20x20x50 cubes of 12 tets, 240,000 tets; 0.1 along z and 1 degree about x per step, 360 steps) and 900 steps of rotation in place, against Gmsh re-meshing the exact geometry of 10 sampled steps (adapt_gmsh_peer.py); and the contact case of thesis 3.7.3 (a cylinder translated 1 per step along its axis into a half tube of the same radius, about 163,000 tets, 45 steps, contact area checked every step) against Gmsh re-meshing its exact geometry at 3 steps; and the assembly mode of thesis 3.7.4 (a crank turning 36 x 10 degrees in a bearing's bore, the two meshed separately, no space mesh, about 24,500 tets; contact conformity checked every step)." ;;
    bench_threads) echo "Parallel loops on a busy machine: Improve's core (phased_odt on a BCC box stretched x3) and the mesh build with validity and quality passes, each with the default thread count and with one thread, idle and with one core kept busy by a spinning child process the program starts and stops (rule: busy, no case more than 10% slower than one thread)." ;;
    bench_deform) echo "FEMorph Deform's core (thesis 2.5): boss_block's boss height 15 -> 20; parameterisation of the whole part (about 110,000 vertices) and of a local region of about 5,000 inner unknowns, repositioning for a new target, and deform + improve at about 700,000 tets against Gmsh re-meshing the changed CAD (gmsh_remesh_peer.py); peak memory per tet. The first run makes the two parts with Gmsh (build/bench-data/deform/, minutes)." ;;
  esac
}

commit="$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)"
if [[ -n "$(git -C "$repo" status --porcelain --untracked-files=no 2>/dev/null)" ]]; then
  commit="$commit with uncommitted changes"
fi
cpu="$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -1)"
machine="$(nproc) cores${cpu:+ ($cpu)}, OMP_NUM_THREADS ${OMP_NUM_THREADS:-unset}"
mkdir -p "$build/benchmarks"
new_dir="$(mktemp -d)"
trap 'rm -rf "$new_dir"' EXIT

status=0
for run in "${runs[@]}"; do
  name="${run%%:*}"
  args=""
  [[ "$run" == *:* ]] && args="${run#*:}"
  if [[ ! " ${all[*]} " == *" $name "* ]]; then
    echo "unknown benchmark $name (one of: ${all[*]})" >&2
    exit 2
  fi
  exe="$build/bin/$name"
  if [[ ! -x "$exe" ]]; then
    echo "=== $name: $exe not built, section kept" >&2
    status=1
    continue
  fi
  log="$build/benchmarks/$name.log"
  echo "=== $name $args (output in $log)"
  start=$(date +%s)
  load_start="$(cut -d' ' -f1 /proc/loadavg)"
  # shellcheck disable=SC2086  # ARGS is a list of options
  if ! (cd "$build" && "$exe" $args) > "$build/benchmarks/$name.out" 2> "$log"; then
    echo "=== $name failed, section kept (see $log)" >&2
    status=1
    continue
  fi
  seconds=$(( $(date +%s) - start ))
  load_end="$(cut -d' ' -f1 /proc/loadavg)"
  {
    echo "<!-- $name: begin -->"
    echo "## $name"
    echo
    describe "$name"
    echo
    echo "Run $(date -u +%Y-%m-%d) on commit $commit; $machine;"
    echo "\`bin/$name${args:+ $args}\` took $seconds s; load average $load_start at its start, $load_end at its end."
    echo
    echo '```text'
    sed 's/\x1b\[[0-9;]*m//g' "$build/benchmarks/$name.out"  # no colour codes
    echo '```'
    echo "<!-- $name: end -->"
  } > "$new_dir/$name.md"
done

# The old file's section of a program, if it has one.
old_section() {
  [[ -f "$results" ]] || return 0
  awk -v b="<!-- $1: begin -->" -v e="<!-- $1: end -->" \
    '$0 == b { on = 1 } on { print } $0 == e { on = 0 }' "$results"
}

{
  cat <<'EOF'
# Benchmark results

The latest figures of FEMorph's benchmark programs (Testing/Benchmarks/bench_*.cpp), as they
printed them. This file is written by the benchmark command; do not edit the sections by hand:

```sh
bash Testing/Benchmarks/run_benchmarks.sh --build build                 # all seven
bash Testing/Benchmarks/run_benchmarks.sh --build build bench_tet_mesh  # one, the others kept
```

bench_tet_mesh and bench_tet_to_hex take a few minutes; bench_segment, bench_improve and bench_deform make large
Gmsh meshes on their first run (into the build folder, reused afterwards) and take longer. The
figures are wall times on the machine named in each section: compare runs on one machine, and
put the figures a change moves into its commit message.
EOF
  for name in "${all[@]}"; do
    echo
    if [[ -f "$new_dir/$name.md" ]]; then
      cat "$new_dir/$name.md"
    else
      section="$(old_section "$name")"
      if [[ -n "$section" ]]; then
        printf '%s\n' "$section"
      else
        echo "<!-- $name: begin -->"
        echo "## $name"
        echo
        describe "$name"
        echo
        echo "Not run yet: \`bash Testing/Benchmarks/run_benchmarks.sh $name\`."
        echo "<!-- $name: end -->"
      fi
    fi
  done
} > "$new_dir/RESULTS.md"
mv "$new_dir/RESULTS.md" "$results"
echo "=== wrote $results"
exit $status
