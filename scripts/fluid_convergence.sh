#!/bin/sh
# Makes docs/gallery/fluid_convergence.png, the README's figure for "How
# wrong is RFT for this strip": the default job (scenarios/paper.toml,
# cycle 3) under each fluid model against its resolution, the table
# docs/FLUIDS.md quotes:
#   - regularized Stokeslets on the centreline, fluid.stokeslet_points_per_mm;
#   - flat plates, fluid.plate_points_across = k (drawn against 1 / k, in
#     which their error is linear, with the line through the two finest to
#     1 / k = 0, the converged swim);
#   - slender-ribbon theory, fluid.ribbon_modes;
#   - RFT with Gray & Hancock's coefficients (the paper's) and calibrated on
#     the plates (fluid.rft_coefficients = "ribbon"), which have no resolution.
# About 90 s of CPU time, a fifth of it the plates at k = 6. A run whose
# folder in OUT already holds its summary.json is not run again (the runs
# are deterministic); delete OUT to start afresh.
#
# Usage: scripts/fluid_convergence.sh [PROGRAM] [OUT]
# (default build/sim/ipmc-swim and out/fluid_convergence); the figure goes to
# docs/gallery/fluid_convergence.png, the table to OUT/swim.csv.
set -eu
program=${1:-build/sim/ipmc-swim}
out=${2:-out/fluid_convergence}
mkdir -p "$out"
table="$out/swim.csv"
echo "model,key,value,com_along_mm,fluid_power_W" > "$table.partial"

# run MODEL KEY VALUE [--set ...]: the default job, cycle 3's row.
run() {
  model=$1 key=$2 value=$3
  shift 3
  dir="$out/$model-$value"
  if [ ! -f "$dir/summary.json" ]; then
    "$program" run scenarios/paper.toml "$@" --set "output.dir=\"$dir\"" > "$dir.log"
  fi
  python3 - "$dir/summary.json" "$model" "$key" "$value" >> "$table.partial" <<'PYTHON'
import json
import sys

summary = json.load(open(sys.argv[1]))
last = summary["per_cycle"][-1]
print(f"{sys.argv[2]},{sys.argv[3]},{sys.argv[4]},{last['com_along_mm']!r},{last['fluid_power_W']!r}")
PYTHON
}

run rft_gray_hancock - 0
run rft_ribbon - 0 --set 'fluid.rft_coefficients="ribbon"'
for ppmm in 0.373 0.746 1.492 2.984; do
  run stokeslets fluid.stokeslet_points_per_mm "$ppmm" --set 'fluid.model="stokeslets"' \
      --set "fluid.stokeslet_points_per_mm=$ppmm"
done
for modes in 4 6 8 9; do
  run ribbon fluid.ribbon_modes "$modes" --set 'fluid.model="ribbon"' \
      --set "fluid.ribbon_modes=$modes"
done
for k in 2 3 4 5 6; do
  run plates fluid.plate_points_across "$k" --set 'fluid.model="plates"' \
      --set "fluid.plate_points_across=$k"
done
mv "$table.partial" "$table"

grep '^rft_gray_hancock' "$table" | cut -d, -f4 > "$out/rft.dat"
grep '^rft_ribbon' "$table" | cut -d, -f4 > "$out/rft_ribbon.dat"
grep '^stokeslets' "$table" | cut -d, -f3,4 | tr , ' ' > "$out/stokeslets.dat"
grep '^ribbon' "$table" | cut -d, -f3,4 | tr , ' ' > "$out/ribbon.dat"
grep '^plates' "$table" | cut -d, -f3,4 | tr , ' ' > "$out/plates.dat"
# The plates' limit: the line in 1 / k through k = 4 and 5.
plates_limit=$(awk '$1 == 4 { s4 = $2 } $1 == 5 { s5 = $2 } END { printf "%.6f", 5 * s5 - 4 * s4 }' "$out/plates.dat")
plates_slope=$(awk '$1 == 4 { s4 = $2 } $1 == 5 { s5 = $2 } END { printf "%.6f", 20 * (s4 - s5) }' "$out/plates.dat")
rft=$(cat "$out/rft.dat")
rft_ribbon=$(cat "$out/rft_ribbon.dat")

gnuplot <<PLOT
set terminal pngcairo size 1500,460 font ",11"
set output "docs/gallery/fluid_convergence.png"
set multiplot layout 1,3 title "The default job's swim per cycle (cycle 3) under each fluid model, against its resolution"
set grid
set yrange [0.35:1.05]
set ylabel "centre of mass per cycle [mm]"
set key top right
limit(x) = $plates_limit
set xlabel "Stokeslets on the centreline: points per mm"
set logscale x 2
plot "$out/stokeslets.dat" using 1:2 with linespoints pt 7 lc rgb "#762a83" title "Stokeslets, centreline", \
     $rft with lines dt 2 lw 2 lc rgb "#1b7837" title "RFT, Gray and Hancock (the paper's)", \
     $rft_ribbon with lines dt 4 lw 2 lc rgb "#2166ac" title "RFT calibrated on the plates", \
     limit(x) with lines dt 3 lw 2 lc rgb "#e08214" title "plates, converged"
set xlabel "slender-ribbon theory: Legendre modes"
unset logscale x
set xrange [3.5:9.5]
plot "$out/ribbon.dat" using 1:2 with linespoints pt 5 lc rgb "#762a83" title "slender-ribbon theory", \
     $rft with lines dt 2 lw 2 lc rgb "#1b7837" title "RFT, Gray and Hancock (the paper's)", \
     $rft_ribbon with lines dt 4 lw 2 lc rgb "#2166ac" title "RFT calibrated on the plates", \
     limit(x) with lines dt 3 lw 2 lc rgb "#e08214" title "plates, converged"
set xlabel "flat plates: 1 / k, k force points across the width"
set xrange [0:0.55]
set xtics ("0" 0, "1/6" 1.0/6, "" 0.2 1, "1/4" 0.25, "1/3" 1.0/3, "1/2" 0.5)
plot "$out/plates.dat" using (1.0/\$1):2 with linespoints pt 9 lc rgb "#762a83" title "plates (k = 2 ... 6)", \
     [0:0.25] $plates_limit + $plates_slope * x with lines dt 3 lw 2 lc rgb "#e08214" title "through k = 4 and 5 to 1 / k = 0", \
     $rft with lines dt 2 lw 2 lc rgb "#1b7837" title "RFT, Gray and Hancock (the paper's)", \
     $rft_ribbon with lines dt 4 lw 2 lc rgb "#2166ac" title "RFT calibrated on the plates"
unset multiplot
PLOT
# The plates extrapolated in 1 / k from two resolutions, (k2 s_k2 - k1 s_k1)
# / (k2 - k1), for the swim and the fluid power: from 4 and 5 the answer,
# from 3 and 4 and from 5 and 6 a measure of its uncertainty.
grep '^plates' "$table" | awk -F, '
  { swim[$3] = $4; power[$3] = $5 }
  END {
    for (k = 3; k <= 5; ++k) {
      printf "plates extrapolated from k = %d and %d: %.6g mm, %.6g W\n", k, k + 1,
             ((k + 1) * swim[k + 1] - k * swim[k]), ((k + 1) * power[k + 1] - k * power[k])
    }
  }'
echo "wrote $table and docs/gallery/fluid_convergence.png"
