#!/bin/sh
# Makes docs/gallery/helix_validation.png and the table docs/VALIDATION.md
# quotes ("Rigid helices in silicone oil"): the rigid helices of Rodenborn,
# Chen, Swinney, Liu & Zhang, PNAS 110, E338-E347 (2013) (models/helices/,
# written by models/helices/make_helices.py), their thrust, torque and drag
# from `ipmc-swim resistance` under RFT (Gray & Hancock's and Lighthill's
# coefficients) and regularized Stokeslets at three resolutions, beside
# the measurements (digitised from their Fig. 2).
#
# Usage: scripts/helix_validation.sh [PROGRAM] [OUT]
# (default build/sim/ipmc-swim and out/helix_validation); the figure goes to
# docs/gallery/helix_validation.png, the table to OUT/helices.csv. About a
# minute of CPU time (most of it the tightest helix at 6 points per mm).
set -eu
program=${1:-build/sim/ipmc-swim}
out=${2:-out/helix_validation}
mkdir -p "$out"
table="$out/helices.csv"
echo "pitch_over_radius,model,points_per_mm,thrust,torque,drag" > "$table.partial"

# Measured (their Fig. 2): thrust / (mu w R^2), torque / (mu w R^3), drag / (mu U R).
cat > "$out/measured.dat" <<'MEASURED'
2.226 6.26 131.9 52.1
3.677 9.60 100.8 47.0
6.509 11.03 81.9 39.4
9.811 9.57 72.7 35.3
15.241 7.84 68.1 34.1
MEASURED

# run RATIO NAME POINTS_PER_MM [OPTIONS]: one helix's row, scaled by mu = 1 Pa s
# (the models') and R = 6.3 mm.
run() {
  ratio=$1 name=$2 points=$3
  shift 3
  json="$out/$ratio-$name-$points.json"
  "$program" resistance "models/helices/rodenborn_$ratio.xml" "$@" --out "$json" > /dev/null
  jq -r --arg ratio "$ratio" --arg name "$name" --arg points "$points" \
    '[$ratio, $name, $points, (.B_N_s | fabs) / (0.0063 * 0.0063),
      .D_N_m_s / (0.0063 * 0.0063 * 0.0063), .A_N_s_m / 0.0063] | @csv' "$json" |
    tr -d '"' >> "$table.partial"
}

for ratio in 2.226 3.677 6.509 9.811 15.241; do
  for coefficients in gray_hancock lighthill; do
    run "$ratio" "rft_$coefficients" - --fluid rft --coefficients "$coefficients"
  done
  for points in 1.5 3 6; do
    run "$ratio" stokeslets "$points" --fluid stokeslets --stokeslet-points-per-mm "$points"
  done
done
mv "$table.partial" "$table"

for series in rft_gray_hancock rft_lighthill; do
  grep ",$series," "$table" | cut -d, -f1,4,5,6 | tr , ' ' > "$out/$series.dat"
done
grep ',stokeslets,6,' "$table" | cut -d, -f1,4,5,6 | tr , ' ' > "$out/stokeslets.dat"

gnuplot <<PLOT
set terminal pngcairo size 1500,460 font ",11"
set output "docs/gallery/helix_validation.png"
set multiplot layout 1,3 title "Rigid helices in silicone oil (Rodenborn et al., PNAS 2013): measured, regularized Stokeslets (6 points per mm) and RFT"
set grid
set xlabel "pitch / helix radius, lambda / R"
set logscale x
set xrange [2:17]
set xtics (2.226, 3.677, 6.509, 9.811, 15.241)
set key top right
# One panel per quantity: column 2 thrust, 3 torque, 4 drag of every .dat.
array ylabels[3] = ["thrust / (mu omega R^2)", "torque / (mu omega R^3)", "drag / (mu U R)"]
array ymax[3] = [40, 240, 330]
do for [panel = 1:3] {
  set ylabel ylabels[panel]
  set yrange [0:ymax[panel]]
  plot "$out/measured.dat" using 1:(column(panel + 1)) with points pt 7 ps 1.5 lc rgb "black" title "measured", \
       "$out/stokeslets.dat" using 1:(column(panel + 1)) with linespoints pt 5 lc rgb "#762a83" title "regularized Stokeslets", \
       "$out/rft_gray_hancock.dat" using 1:(column(panel + 1)) with linespoints dt 2 pt 4 lc rgb "#1b7837" title "RFT, Gray and Hancock", \
       "$out/rft_lighthill.dat" using 1:(column(panel + 1)) with linespoints dt 4 pt 6 lc rgb "#2166ac" title "RFT, Lighthill"
}
unset multiplot
PLOT
cat "$table"
