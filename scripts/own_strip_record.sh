#!/bin/sh
# Makes scenarios/own_strip.csv, the bench record of "your own strip" that
# docs/OWN_ROBOT.md starts from: the project's bench on the clamped
# flagellum generated with a plant other than the paper's (every link
# G1 with a0 = 0.52 mm/V, b1 = 0.032 s, b2 = 0.004 s^2), link 1 driven by a
# 3 V chirp from 0.05 to 10 Hz over 100 s and recorded at 100 Hz, its
# deflection with Gaussian noise of 0.01 mm added (seed 7), three columns
# kept. tests/identification_round_trip_test.cc identifies it.
#
# Usage: scripts/own_strip_record.sh [PROGRAM] [OUT]
# (default build/sim/ipmc-swim and scenarios/own_strip.csv)
set -eu
program=${1:-build/sim/ipmc-swim}
out=${2:-scenarios/own_strip.csv}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
"$program" generate --clamped --timestep-s 5e-4 --a0-mm-per-v 0.52,0.52,0.52 \
    --b1 0.032,0.032,0.032 --b2-s2 0.004,0.004,0.004 --out "$scratch/strip.xml"
"$program" bench --model "$scratch/strip.xml" --signal chirp --links 1 --amplitude-v 3 \
    --start-hz 0.05 --end-hz 10 --duration-s 100 --sample-rate-hz 100 --out "$scratch/bench.csv"
python3 - "$scratch/bench.csv" "$scratch/own_strip.csv" <<'PYTHON'
import csv
import random
import sys

noise = random.Random(7)
with open(sys.argv[1]) as bench, open(sys.argv[2], "w", newline="") as out:
    rows = csv.DictReader(bench)
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["time_s", "voltage1_V", "relative1_mm"])
    for row in rows:
        deflection_mm = float(row["relative1_mm"]) + noise.gauss(0.0, 0.01)
        writer.writerow([row["time_s"], "%.6g" % float(row["voltage1_V"]), "%.6g" % deflection_mm])
PYTHON
mv "$scratch/own_strip.csv" "$out"
