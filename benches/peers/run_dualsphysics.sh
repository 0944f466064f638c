#!/usr/bin/env bash
# DualSPHysics's CPU solver (v5.4) and tumble side by side on one 2D dam break: the column of
# tumble's dam_break_speed example at 67 particles over its height (2,211 fluid particles, the
# same lattice, kernel, viscosity, density diffusion, sound speed and fixed time step in both;
# benches/peers/dualsphysics_dam_break_2d.xml and tumble_dam_break_2d.toml). Prints fluid
# particle-steps/s of each on 1 and 2 threads and their ratio, then the surge front of each at
# three of Martin & Moyce's times. DualSPHysics computes the interactions in f32 (positions in
# f64 with SavePosDouble) and its walls are its own dynamic boundary particles (DBC); tumble is
# f64 throughout with Adami's walls.
#   DSPH=/path/to/DualSPHysics benches/peers/run_dualsphysics.sh
# DSPH is a checkout of https://github.com/DualSPHysics/DualSPHysics; its CPU solver is built
# there with its Makefile_cpu (without Chrono and MoorDyn+) when missing. GENCASE overrides the
# case generator (default: the checkout's bin/linux/GenCase_linux64).
set -euo pipefail
cd "$(dirname "$0")/../.."
: "${DSPH:?set DSPH to a DualSPHysics checkout}"
DSPH=$(cd "$DSPH" && pwd)
SOLVER=${SOLVER:-$DSPH/bin/linux/DualSPHysics5.4CPU_linux64}
GENCASE=${GENCASE:-$DSPH/bin/linux/GenCase_linux64}
TMAX=0.19
if [ ! -x "$SOLVER" ]; then
    (cd "$DSPH/src/source" && make -j"$(nproc)" -f Makefile_cpu COMPILE_CHRONO=NO COMPILE_MOORDYNPLUS=NO)
fi
work=$PWD/target/peers/dualsphysics
rm -rf "$work" && mkdir -p "$work"
cp benches/peers/dualsphysics_dam_break_2d.xml "$work/DamBreak2D_Def.xml"
(cd "$work" && "$GENCASE" DamBreak2D_Def case/DamBreak2D -save:all >gencase.txt)
cargo build --quiet --release -p tumble-sph --example dam_break_speed
cargo build --quiet --release
"$SOLVER" -ver 2>/dev/null | head -1 || true
# Fluid particle-steps/s from a run's Run.csv (fields separated by ';', thousands by ',').
rate() {
    python3 - "$1" <<'PY'
import csv, sys
rows = list(csv.reader(open(sys.argv[1]), delimiter=';'))
d = dict(zip(rows[0], rows[1]))
n = lambda s: float(s.replace(',', ''))
print(f"{(n(d['Np']) - n(d['Nbound'])) * n(d['Steps']) / n(d['TSimul']):.3e} {int(n(d['Steps']))}")
PY
}
for threads in 1 2; do
    (cd "$work" && OMP_NUM_THREADS=$threads "$SOLVER" case/DamBreak2D speed$threads -ompthreads:$threads -sv:none -svtimers:0 \
        -tmax:$TMAX >speed$threads.txt)
    read -r dsph steps < <(rate "$work/speed$threads/Run.csv")
    line=$(target/release/examples/dam_break_speed 2 67 "$steps" "$threads")
    tumble=$(echo "$line" | sed 's/.*: \([0-9.e+-]*\) fluid particle-steps.*/\1/')
    echo "threads $threads: $steps steps; DualSPHysics $dsph, tumble $tumble fluid particle-steps/s; tumble/DualSPHysics $(python3 -c "print(f'{$tumble / $dsph:.2f}')")"
done
# Fronts: DualSPHysics's particles every 0.0025 s (CSV, type 3 = fluid), tumble's front probe.
(cd "$work" && "$SOLVER" case/DamBreak2D fronts -ompthreads:2 -sv:csv -svtimers:0 -tmax:$TMAX >fronts.txt)
target/release/tumble run benches/peers/tumble_dam_break_2d.toml --quiet --out "$work/tumble" >/dev/null
python3 - "$work" <<'PY'
import csv, glob, math, os, sys
work = sys.argv[1]
a, g = 0.1, 9.81
times = {int(r['Part']): float(r['TimeStep [s]']) for r in csv.DictReader(open(os.path.join(work, 'fronts', 'RunPARTs.csv')), delimiter=';')
         if (r.get('Part') or '').strip().isdigit()}
dsph = []
for path in sorted(glob.glob(os.path.join(work, 'fronts', 'data', 'PartCsv_*.csv'))):
    with open(path) as f:
        next(f)
        xs = [float(c[0]) for c in (line.split(';') for line in f) if int(c[8]) == 3]
    dsph.append((times[int(path[-8:-4])], max(xs)))
tumble = [(float(r['t']), float(r['front'])) for r in csv.DictReader(open(os.path.join(work, 'tumble', 'probe_front.csv')))]
def at(rows, t):
    for (t0, x0), (t1, x1) in zip(rows, rows[1:]):
        if t0 <= t <= t1:
            return x0 + (x1 - x0) * (t - t0) / (t1 - t0)
# Martin & Moyce (1952), n² = 2: Z = x/a against T = t sqrt(2g/a).
for T, z in [(1.219, 1.474), (1.997, 2.292), (2.547, 2.995)]:
    t = T / math.sqrt(2 * g / a)
    zd, zt = at(dsph, t) / a, at(tumble, t) / a
    print(f"T = {T}: Martin & Moyce Z = {z}; DualSPHysics {zd:.3f} ({100 * (zd / z - 1):+.1f} %), tumble {zt:.3f} ({100 * (zt / z - 1):+.1f} %)")
PY
