#!/usr/bin/env bash
# PySPH's own 2D dam break (pysph.examples.dam_break_2d: a column 1 m wide and 2 m high in a
# tank 4 m wide, dx = 0.03 m, WCSPH) against tumble's example of the same column at the same
# resolution and the same kernel reach (h = 1.5 dx, support 3 dx: PySPH's cubic spline, tumble's
# Wendland C2), on 1 and 2 threads: fluid particle-steps/s of each and their ratio.
# Both codes evaluate the rates twice per step; PySPH's step is 0.125 h/c0, tumble's
# 0.25 h/(1.1 c0), so per unit of simulated time tumble takes 0.55 times PySPH's steps.
#   benches/peers/run_pysph.sh        (env: TF=0.2 simulated seconds for PySPH, STEPS=1000 for tumble)
set -euo pipefail
cd "$(dirname "$0")/../.."
python3 -c "import pysph" 2>/dev/null || pip install pysph
cargo build --quiet --release -p tumble-sph --example dam_break_speed
DX=0.03
HDX=1.5
TF=${TF:-0.2}
STEPS=${STEPS:-1000}
python3 -c "import pysph; print('PySPH', pysph.__version__)"
for threads in 1 2; do
    openmp=""
    if [ "$threads" -gt 1 ]; then openmp="--openmp"; fi
    out=$(OMP_NUM_THREADS=$threads python3 -m pysph.examples.dam_break_2d --dx $DX --hdx $HDX --tf "$TF" $openmp \
        --disable-output -d target/pysph_dam_break 2>&1)
    fluid=$(echo "$out" | awk '/fluid:/ {print $2}')
    seconds=$(echo "$out" | awk '/Run took/ {print $3}')
    pysph=$(python3 -c "
import math
h = $HDX * $DX
c0 = 10 * math.sqrt(2 * 9.81 * 2.0)
steps = round($TF / (0.125 * h / c0))
print(f'{$fluid * steps / $seconds:.3e}')")
    line=$(target/release/examples/dam_break_speed 2 67 "$STEPS" "$threads")
    tumble=$(echo "$line" | sed 's/.*: \([0-9.e+-]*\) fluid particle-steps.*/\1/')
    echo "threads $threads: PySPH $fluid fluid particles, $pysph; tumble $tumble fluid particle-steps/s; tumble/PySPH $(python3 -c "print(f'{$tumble / $pysph:.2f}')")"
done
