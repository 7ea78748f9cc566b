#!/bin/bash
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# The side-by-side of algorithms/odometry/README.md ("KISS-ICP side by side"): simulated captures
# of the sample office exported as scan folders, every fifth scan kept, real single frames
# repeated, then `bimslam odometry` LiDAR-only and kiss_icp_peer run interleaved on each folder,
# REPS times, and the table printed by summarise.py. Downloads nothing.
#   tests/peers/kiss_icp/side_by_side.sh BIN_DIR WORK_DIR      (BIN_DIR: build/release/bin)
set -euo pipefail
bin=$(readlink -f "$1"); work=$2; reps=${REPS:-3}
here=$(dirname "$(readlink -f "$0")")
data=${BIMSLAM_DATA:-$here/../../../../shared/data}
B=$bin/bimslam; K=$bin/kiss_icp_peer
mkdir -p "$work"; cd "$work"

# Captures: Go1 and hand-held, OS1-32 (60 s) and OS1-128 (30 s), seeds 1 and 2.
[ -f office.ifc ] || $B bim sample -o office.ifc > /dev/null
for sensor in OS1-32 OS1-128; do
  dur=60; [ $sensor = OS1-128 ] && dur=30
  for platform in go1 handheld; do
    for seed in 1 2; do
      name=${platform}_${sensor}_s${seed}
      [ -f cap_$name/ground_truth.tum ] ||
        $B simulate --model office.ifc --platform $platform --sensor $sensor --duration $dur \
          --seed $seed -o cap_$name --overwrite > /dev/null
      [ -f exp_$name/times.txt ] || $B ouster export cap_$name --all -o exp_$name --overwrite > /dev/null
      # 2 Hz: every fifth scan of the export (links), its times, the same ground truth.
      if [ ! -f e5_$name/times.txt ]; then
        mkdir -p e5_$name
        ls exp_$name/*.pcd | sort | awk 'NR % 5 == 1' | while read -r f; do
          ln -sf "$(readlink -f "$f")" e5_$name/; done
        awk 'NR % 5 == 1' exp_$name/times.txt > e5_$name/times.txt
        cp exp_$name/ground_truth.tum e5_$name/
      fi
    done
  done
done
# Real recordings of ../shared/data/ouster: one frame each, so a static sensor is all they can
# give: the frame repeated 50 times at 10 Hz.
for cap in OS-2-128-U1_v2.3.0_1024x10 OS-0-128-U1_v2.3.0_1024x10 OS-1-32-G_v2.1.1_1024x10; do
  [ -f "$data/ouster/$cap.pcap" ] || { echo "no $data/ouster/$cap.pcap: skipped"; continue; }
  [ -f rep_$cap/times.txt ] && continue
  $B ouster export "$data/ouster/$cap.pcap" --all -o real1_$cap --overwrite > /dev/null
  mkdir -p rep_$cap
  src=$(readlink -f real1_$cap/000000.pcd); t0=$(head -1 real1_$cap/times.txt)
  for k in $(seq 0 49); do ln -sf "$src" rep_$cap/$(printf %06d $k).pcd; done
  awk -v t0="$t0" 'BEGIN { for (k = 0; k < 50; ++k) printf "%.9f\n", t0 + 0.1 * k }' > rep_$cap/times.txt
done

# Interleaved runs: ours (LiDAR only, no budget: deterministic) and KISS-ICP on the same folder,
# the order swapped on every other repetition; the load at each run's start kept beside it.
shopt -s nullglob
for rep in $(seq 1 "$reps"); do
  for dir in exp_*/ e5_*/ rep_*/; do
    input=${dir%/}
    mkdir -p runs/$input
    order="ours kiss"; [ $((rep % 2)) = 0 ] && order="kiss ours"
    for tool in $order; do
      out=runs/$input/${tool}_r$rep
      cut -d' ' -f1-3 /proc/loadavg | sed "s/^/$(date +%T) /" > $out.load
      if [ $tool = ours ]; then
        $B odometry $input -o $out --no-imu --budget-ms 10000 --overwrite --json > $out.json
      else
        $K $input -o $out --json > $out.json
      fi
      echo "$(date +%T) rep $rep $input $tool, load $(cut -d' ' -f1 /proc/loadavg)"
    done
  done
done
BIMSLAM=$B python3 "$here/summarise.py" .
