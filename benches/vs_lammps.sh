#!/usr/bin/env bash
# floe against LAMMPS in the same sitting: contact updates per second
# (contacts x steps / wall seconds of the stepping alone, setup excluded)
# of floe's step benchmark (crates/floe-dem/examples/step_profile.rs: ~N
# diamonds sheared in a channel periodic along x) and of two LAMMPS
# set-ups of the same channel: discs with tangential history
# (benches/lammps/in.discs, pair gran/hooke/history) and rounded rhombi
# (benches/lammps/in.polygons, pair body/rounded/polygon). Each on one
# core and on two (floe: 2 rayon threads; LAMMPS: mpirun -np 2), the six
# runs alternated ROUNDS times; keeps each run's best round and prints a
# table and the ratios. docs/performance.md ("Against LAMMPS") quotes it.
#
#   cargo build --release -p floe-dem --example step_profile
#   benches/vs_lammps.sh [N_PARTICLES] [ROUNDS] [STEPS]
#
# Defaults: 10000 particles, 3 rounds, 200 timed steps per run (LAMMPS
# also runs 100 untimed steps first; floe's pack has taken 20). FLOE_LAW
# (amontons, default, or rate-state) picks floe's friction law. Installs
# and builds nothing: LAMMPS is Debian's `lammps` package (`make lammps`).
set -euo pipefail
cd "$(dirname "$0")/.."

n=${1:-10000}
rounds=${2:-3}
steps=${3:-200}
law=${FLOE_LAW:-amontons}
warmup=100
for v in "$n" "$rounds" "$steps"; do
  [[ $v =~ ^[1-9][0-9]*$ ]] || { echo "usage: $0 [N_PARTICLES] [ROUNDS] [STEPS] (positive integers; got '$v')" >&2; exit 2; }
done
case $law in
  amontons | rate-state) ;;
  *) echo "error: FLOE_LAW must be amontons or rate-state, not '$law'" >&2; exit 2 ;;
esac

floe=${CARGO_TARGET_DIR:-target}/release/examples/step_profile
if [ ! -x "$floe" ]; then
  echo "error: $floe not found; build it first: cargo build --release -p floe-dem --example step_profile" >&2
  exit 1
fi
if ! command -v lmp >/dev/null 2>&1; then
  echo "error: lmp (LAMMPS) not found; on Debian or Ubuntu: make lammps (apt-get install lammps)" >&2
  exit 1
fi
for pkg in GRANULAR BODY; do
  if ! lmp -h 2>/dev/null | sed -n '/^Installed packages:/,/^List of individual/p' | grep -qw "$pkg"; then
    echo "error: this lmp lacks the $pkg package, which benches/lammps/ needs" >&2
    exit 1
  fi
done
mpi=()
if command -v mpirun >/dev/null 2>&1; then
  mpi=(mpirun -np 2)
  if mpirun --version 2>&1 | grep -q "Open MPI"; then
    # Open MPI refuses root without this, and more processes than cores
    # without --oversubscribe (which also makes idle processes yield).
    if [ "$(id -u)" = 0 ]; then mpi+=(--allow-run-as-root); fi
    if [ "$(nproc 2>/dev/null || echo 1)" -lt 2 ]; then mpi+=(--oversubscribe); fi
  fi
else
  echo "note: no mpirun: LAMMPS runs on one process only" >&2
fi

here=$PWD
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export OMP_NUM_THREADS=1

# floe THREADS: prints "particles contacts rate" (contact updates per second).
run_floe() {
  local out
  out=$("$floe" "$n" "$law" "$1" "$steps" 2>"$dir/floe.err") || {
    echo "error: $floe failed:" >&2; cat "$dir/floe.err" >&2; exit 1; }
  # "10125 floes, 29867 contacts, ..., 15.21 ms/step, 509 ns per contact"
  awk '/ floes, .* contacts, .* ms\/step/ {
         f = $1
         for (i = 1; i <= NF; i++) {
           if ($i == "contacts,") c = $(i - 1)
           if ($i == "ms/step,") ms = $(i - 1)
           if ($i == "ns" && $(i + 1) == "per") ns = $(i - 1)
         }
       }
       END {
         if (c == "" || ms + 0 <= 0 || ns + 0 <= 0) { print "no timing in the output of step_profile" > "/dev/stderr"; exit 1 }
         # Both are rounded (to 0.01 ms and 1 ns): take the finer one.
         rate = (0.005 / ms < 0.5 / ns) ? c / (ms * 1e-3) : 1e9 / ns
         printf "%d %d %.6g\n", f, c, rate
       }' <<<"$out" || { echo "error: could not read the timing of $floe" >&2; exit 1; }
}

# LAMMPS INPUT PROCS ROUND: prints "particles contacts rate". The input's
# second "Loop time" is the timed run.
run_lammps() {
  local input=$1 procs=$2 round=$3 out contacts
  local cmd=(lmp -nocite -log none -in "$here/benches/lammps/in.$input"
    -var n "$n" -var steps "$steps" -var warmup "$warmup")
  if [ "$input" = polygons ]; then
    cmd+=(-var data "$here/benches/lammps/data.diamonds")
    # The vertices after the run, for the contact count (first round only:
    # a rerun on as many processes ends in the same state).
    if [ "$round" = 1 ]; then cmd+=(-var dump "$dir/vertices.$procs"); fi
  fi
  if [ "$procs" = 2 ]; then cmd=("${mpi[@]}" "${cmd[@]}"); fi
  out=$(cd "$dir" && "${cmd[@]}" 2>&1) || {
    echo "error: ${cmd[*]} failed:" >&2; tail -n 20 <<<"$out" >&2; exit 1; }
  if [ "$input" = discs ]; then
    contacts=$(sed -n 's/^BENCH discs atoms [0-9]* contacts \([0-9]*\) .*/\1/p' <<<"$out")
  else
    if [ "$round" = 1 ]; then
      # r: the rounding radius of data.diamonds' rhombi.
      awk -v r=0.05 -f benches/lammps/count_contacts.awk "$dir/vertices.$procs" >"$dir/contacts.$procs"
    fi
    contacts=$(cut -d' ' -f1 "$dir/contacts.$procs")
  fi
  awk -v c="$contacts" -v procs="$procs" -v steps="$steps" '
    /^Loop time of / { if (++k == 2) { t = $4; p = $6; s = $9; a = $12 } }
    END {
      if (k < 2 || c == "") { print "no timed run or contact count in the LAMMPS output" > "/dev/stderr"; exit 1 }
      if (p != procs) { printf "LAMMPS ran on %s processes, not %s (lmp built without MPI?)\n", p, procs > "/dev/stderr"; exit 1 }
      printf "%d %d %.6g\n", a, c, c * s / t
    }' <<<"$out" || { echo "error: could not read the timing of ${cmd[*]}" >&2; exit 1; }
}

names=("floe $law" "floe $law" "LAMMPS discs" "LAMMPS discs" "LAMMPS polygons" "LAMMPS polygons")
procs=(1 2 1 2 1 2)
best=(0 0 0 0 0 0)
particles=(0 0 0 0 0 0)
contacts=(0 0 0 0 0 0)
echo "$n particles, $steps timed steps, $rounds rounds; contact updates per second (millions) of"
echo "floe 1 thread, 2 threads; LAMMPS discs 1 process, 2; LAMMPS polygons 1 process, 2:"
for r in $(seq 1 "$rounds"); do
  line="round $r:"
  for k in 0 1 2 3 4 5; do
    if [ "${procs[$k]}" = 2 ] && [ ${#mpi[@]} = 0 ] && [ "$k" -ge 2 ]; then
      line+=" n/a"; continue
    fi
    case $k in
      0 | 1) res=$(run_floe "${procs[$k]}") ;;
      2 | 3) res=$(run_lammps discs "${procs[$k]}" "$r") ;;
      *) res=$(run_lammps polygons "${procs[$k]}" "$r") ;;
    esac
    read -r np c rate <<<"$res"
    particles[k]=$np
    contacts[k]=$c
    best[k]=$(awk -v a="${best[$k]}" -v b="$rate" 'BEGIN { print (b > a ? b : a) }')
    line+=$(awk -v b="$rate" 'BEGIN { printf " %.2f", b / 1e6 }')
  done
  echo "$line"
done

echo
printf '%-22s %5s %9s %9s %9s %22s\n' "run" "cores" "particles" "contacts" "per part." "best M contact upd/s"
for k in 0 1 2 3 4 5; do
  [ "${best[$k]}" = 0 ] && continue
  awk -v name="${names[$k]}" -v p="${procs[$k]}" -v c="${contacts[$k]}" -v n="${particles[$k]}" -v b="${best[$k]}" \
    'BEGIN { printf "%-22s %5d %9d %9d %9.2f %22.2f\n", name, p, n, c, c / n, b / 1e6 }'
done
echo
ratio() { awk -v a="$2" -v b="$3" -v what="$1" 'BEGIN { if (a > 0 && b > 0) printf "%-52s %.2f\n", what, a / b; else printf "%-52s n/a\n", what }'; }
ratio "floe (1 core) / LAMMPS discs (1 core), target 0.6:" "${best[0]}" "${best[2]}"
ratio "floe (1 core) / LAMMPS polygons (1 core):" "${best[0]}" "${best[4]}"
ratio "speed-up on 2 cores, floe (2 threads):" "${best[1]}" "${best[0]}"
ratio "speed-up on 2 cores, LAMMPS discs (2 processes):" "${best[3]}" "${best[2]}"
ratio "speed-up on 2 cores, LAMMPS polygons (2 processes):" "${best[5]}" "${best[4]}"
