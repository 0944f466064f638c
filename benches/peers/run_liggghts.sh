#!/usr/bin/env bash
# LIGGGHTS peer run of the dense packed bed benchmark (see README.md, liggghts_bed.in).
#
# usage: benches/peers/run_liggghts.sh [results.csv]
# env:   RANKS="1 2"  NWARM=200  NSTEPS=2000
#
# Prints one line per rank count:
#   liggghts ranks=P steps=S particles=N wall_s=X particle_steps_per_s=Y
# plus a "# state ..." line (end-of-run KE, max speed, z range, neighbour builds).
# If a CSV path is given, the same numbers are written there (one row per rank count).
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
INPUT="$HERE/liggghts_bed.in"
CSV="${1:-}"
RANKS="${RANKS:-1 2}"
NWARM="${NWARM:-200}"
NSTEPS="${NSTEPS:-2000}"

# ---- install if missing (Debian/Ubuntu package liggghts 3.8.0 + Open MPI) ----
if ! command -v liggghts >/dev/null 2>&1 || ! command -v mpirun >/dev/null 2>&1; then
    SUDO=""
    if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
    export DEBIAN_FRONTEND=noninteractive
    $SUDO apt-get update -qq
    $SUDO apt-get install -y -qq liggghts openmpi-bin >/dev/null
fi

# Open MPI refuses to run as root unless told otherwise.
export OMPI_ALLOW_RUN_AS_ROOT=1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

NCPU="$(nproc)"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT

if [ -n "$CSV" ]; then
    echo "engine,ranks,steps,particles,wall_s,particle_steps_per_s,ke_end_J,vmax_end_m_s,zmin_end_m,zmax_end_m,neigh_builds,version" > "$CSV"
fi

for P in $RANKS; do
    OVERSUB=""
    if [ "$P" -gt "$NCPU" ]; then OVERSUB="--oversubscribe"; fi
    OUTF="$WORK/out_np$P.txt"
    ( cd "$WORK" && mpirun $OVERSUB -np "$P" liggghts -in "$INPUT" \
        -var nwarm "$NWARM" -var nsteps "$NSTEPS" -log none -echo none -nocite ) > "$OUTF" 2>&1 || {
        echo "liggghts run with $P ranks failed; output:" >&2; tail -40 "$OUTF" >&2; exit 1; }

    # "Loop time of X on P procs for S steps with N atoms" -- the 2nd one is the timed run
    LOOP="$(grep '^Loop time of' "$OUTF" | sed -n 2p)"
    if [ -z "$LOOP" ]; then echo "no timed Loop time line for $P ranks" >&2; tail -40 "$OUTF" >&2; exit 1; fi
    read -r X PP S N <<<"$(echo "$LOOP" | awk '{print $4, $6, $9, $12}')"
    Y="$(awk -v n="$N" -v s="$S" -v x="$X" 'BEGIN{printf "%.6g", n*s/x}')"

    # last thermo row of the timed run: step atoms ke rke vmax zmin zmax
    STATE="$(awk '/^ +Step +Atoms/{hdr++} hdr==2 && $1 ~ /^[0-9]+$/ {last=$0} END{print last}' "$OUTF")"
    read -r _STEP ATOMS KE RKE VMAX ZMIN ZMAX <<<"$STATE"
    VERSION="$(grep -m1 -o 'LIGGGHTS-PUBLIC [0-9.]*' "$OUTF" || true)"
    BUILDS="$(grep '^Neighbor list builds' "$OUTF" | sed -n 2p | awk '{print $NF}')"

    echo "liggghts ranks=$PP steps=$S particles=$N wall_s=$X particle_steps_per_s=$Y"
    echo "# state ranks=$PP atoms_end=$ATOMS ke_end_J=$KE rot_ke_end_J=$RKE vmax_end_m_s=$VMAX zmin_end=$ZMIN zmax_end=$ZMAX neigh_builds=$BUILDS ($VERSION)"
    if [ -n "$CSV" ]; then
        echo "liggghts,$PP,$S,$N,$X,$Y,$KE,$VMAX,$ZMIN,$ZMAX,$BUILDS,$VERSION" >> "$CSV"
    fi
done
