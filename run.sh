#!/usr/bin/env bash
# Installs what is missing, builds, and runs the default job: the paper's
# three-link swimmer under closed-loop distributed actuation
# (scenarios/paper.toml), filmed as it runs, then draws its figures into
# out/default. Extra arguments replace the default job's.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$root/scripts/setup.sh"
ipmc_install_packages
ipmc_build "$root"
if [ "$#" -gt 0 ]; then
  exec "$root/build/sim/ipmc-swim" "$@"
fi
bin="$root/build/sim/ipmc-swim"
out="$root/out/default"
"$bin" run "$root/scenarios/paper.toml" --out "$out" --video "$out/swim.mp4"
"$bin" bode --controller pid --links 3 --out "$out/bode" > /dev/null
"$bin" step --controller pid --no-clamp --out "$out/step" > /dev/null
# Each figure as PDF (for a paper) and PNG (for a screen).
for format in pdf png; do
  for kind in tracking waveform surface trajectory; do
    "$bin" plot "$kind" "$out/timeseries.csv" --out "$out/$kind.$format"
  done
  "$bin" plot bode "$out/bode/bode.csv" --out "$out/bode.$format"
  "$bin" plot step "$out/step/step.csv" --out "$out/step.$format"
done
echo "ipmc-swim: results, video and figures in $out"
