#!/usr/bin/env bash
# Side by side: tumble and LIGGGHTS on the same 100,000-sphere packed bed, same
# stiffness, damping, friction, particles and dt, at 1 and 2 threads / MPI ranks.
# Both time 2000 steps after 200 warm-up steps (tumble: the 2200-step run minus the
# 200-step run). Prints particle-steps/s, the ratio, and a physics cross-check
# (kinetic energy at step 2200 in both codes).
#
# TANGENTIAL=history compares the bed with tangential springs (scenes/bench/packed_bed_history.toml
# against LIGGGHTS `tangential history`) instead of the history-free one.
#
# usage: [TANGENTIAL=history] benches/peers/compare.sh [results.md]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$ROOT"
OUT="${1:-}"
REPEATS="${REPEATS:-2}"
cargo build --release --quiet
TANGENTIAL="${TANGENTIAL:-no_history}"
case "$TANGENTIAL" in
    history) SCENE=scenes/bench/packed_bed_history.toml ;;
    no_history) SCENE=scenes/bench/packed_bed.toml ;;
    *) echo "TANGENTIAL must be history or no_history, got $TANGENTIAL" >&2; exit 2 ;;
esac
DT=3.5e-5
TMP="$(mktemp -d)"

wall() { # wall seconds of `tumble run` for N steps at T threads
    ./target/release/tumble run "$SCENE" --threads "$2" --duration "$(python3 -c "print($1 * $DT)")" --out "$TMP/run" --quiet >/dev/null
    python3 -c "import json; print(json.load(open('$TMP/run/summary.json'))['wall_seconds'])"
}
ke() { python3 -c "import csv; print(list(csv.DictReader(open('$TMP/run/observables.csv')))[-1]['kinetic_energy'])"; }

declare -A TUMBLE
for t in 1 2; do
    best=1e9
    for _ in $(seq "$REPEATS"); do
        short=$(wall 200 "$t"); long=$(wall 2200 "$t")
        best=$(python3 -c "print(min($best, $long - $short))")
    done
    TUMBLE[$t]=$(python3 -c "print(100000 * 2000 / $best)")
    echo "tumble threads=$t steps=2000 particles=100000 wall_s=$best particle_steps_per_s=${TUMBLE[$t]}"
done
KE_TUMBLE=$(ke)

REPEATS="$REPEATS" TANGENTIAL="$TANGENTIAL" benches/peers/run_liggghts.sh "$TMP/liggghts.csv" | tee "$TMP/liggghts.txt"
KE_LIGGGHTS=$(python3 -c "import csv; print(list(csv.DictReader(open('$TMP/liggghts.csv')))[-1]['ke_end_J'])")

{
    echo "Tangential model: $TANGENTIAL ($SCENE)"
    echo
    echo "| threads / ranks | tumble [particle-steps/s] | LIGGGHTS [particle-steps/s] | tumble / LIGGGHTS |"
    echo "|---|---|---|---|"
    for t in 1 2; do
        l=$(python3 -c "import csv; print([r for r in csv.DictReader(open('$TMP/liggghts.csv')) if r['ranks'] == '$t'][0]['particle_steps_per_s'])")
        python3 -c "print('| $t | %.3e | %.3e | %.2f |' % (${TUMBLE[$t]}, $l, ${TUMBLE[$t]} / $l))"
    done
    python3 -c "print('\nKinetic energy at step 2200: tumble %.6f J, LIGGGHTS %.6f J (difference %.2f %%).' % ($KE_TUMBLE, $KE_LIGGGHTS, 100 * abs($KE_TUMBLE / $KE_LIGGGHTS - 1)))"
    echo "Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
} | tee "$TMP/table.md"
[ -n "$OUT" ] && cp "$TMP/table.md" "$OUT"
rm -rf "$TMP"
