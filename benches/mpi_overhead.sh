#!/usr/bin/env bash
# Two processes against two threads on one machine: `mpirun -np 2 floe run
# --threads 1` against `floe run --threads 2` on a ~1e5-floe channel
# (scenarios/shear_zone.toml with floes 5.8x smaller: 100,398 free floes,
# 1,898 glued to the walls, a stress-controlled wall), alternated ROUNDS
# times in one sitting; prints each run's steps/s and the ratio of the
# medians. docs/hpc.md quotes it.
#
#   make build && benches/mpi_overhead.sh [ROUNDS] [DURATION_S]
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-3}
duration=${2:-250}
floe=target/release/floe
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
sed -e 's/diagonals_m = \[1700.0, 1000.0\]/diagonals_m = [290.0, 170.0]/' \
    -e 's/glue_depth_m = 900.0/glue_depth_m = 150.0/' \
    -e "s/^duration_s = .*/duration_s = $duration.0/" \
    -e 's/^snapshot_every_s = .*/snapshot_every_s = 1.0e6/' \
    -e 's/^observables_every_s = .*/observables_every_s = 1.0e6/' \
    scenarios/shear_zone.toml > "$dir/channel.toml"
root=""; [ "$(id -u)" = 0 ] && root="--allow-run-as-root"
rate() { sed -n 's/.*(\([0-9.]*\) steps\/s.*/\1/p'; }
threads=(); procs=()
for r in $(seq 1 "$rounds"); do
  t=$("$floe" run "$dir/channel.toml" -o "$dir/t.h5" --force -q --threads 2 2>&1 | rate)
  p=$(mpirun $root -np 2 "$floe" run "$dir/channel.toml" -o "$dir/p.h5" --force -q --threads 1 2>&1 | rate)
  echo "round $r: --threads 2: $t steps/s; mpirun -np 2: $p steps/s"
  threads+=("$t"); procs+=("$p")
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
mt=$(median "${threads[@]}"); mp=$(median "${procs[@]}")
echo "median: --threads 2 $mt steps/s, mpirun -np 2 $mp steps/s; time per step, processes over threads: $(awk -v a="$mt" -v b="$mp" 'BEGIN {printf "%.3f", a / b}')"
