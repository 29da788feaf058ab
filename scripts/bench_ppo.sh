#!/usr/bin/env bash
# PPO training throughput (BENCHMARKS.md "PPO training"): environment steps per second, inference
# and updates included, for 1, 2 and 4 in-process simulators (and 2 with --overlap) and for 2
# simulators over ROS
# (launch/simulators.launch on a private master). Each configuration trains STEPS steps in a
# scratch folder with the shipped backbone (frozen) on Sweet Home 3D chairs and tables, 256 px;
# the rate quoted is the median over updates 6.. of 200 / (that update's wall time), so the
# first scenes' mesh loading is left out, and where the time went (environments / inference /
# optimisation) is summed over the same updates.
# Usage: scripts/bench_ppo.sh [STEPS]   (default 4000). Needs the built workspace (make build).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
steps="${1:-4000}"
devel="$root/.build_ws/devel"
trainer="$devel/lib/occlusion_env/occlusion_train_ppo"
[[ -x "$trainer" ]] || { echo "bench_ppo.sh: $trainer not built (make build)" >&2; exit 1; }
scratch=$(mktemp -d)

summarise() {  # LABEL RUN_DIR
  python3 "$root/scripts/ppo_rate.py" --no-header --from-update 6 --label "$1" "$2"
}

echo "| environments | steps/s (median) | environments | inference | optimisation | updates |"
echo "|---|---:|---:|---:|---:|---:|"
for n in 1 2 4; do
  "$trainer" --out "$scratch/in_process_$n" --envs "$n" --steps "$steps" >/dev/null 2>&1
  summarise "$n in process" "$scratch/in_process_$n"
done
"$trainer" --out "$scratch/overlap_2" --envs 2 --overlap --steps "$steps" >/dev/null 2>&1
summarise "2 in process, --overlap" "$scratch/overlap_2"

# Two simulators over ROS on this machine.
(
  set +u  # ROS's setup scripts read unset variables
  source "$root/test/private_roscore.sh" "$devel/setup.bash"
  roslaunch occlusion_env simulators.launch count:=2 >"$scratch/sims.log" 2>&1 &
  pids+=($!)
  for ns in sim0 sim1; do
    for _ in $(seq 150); do rosservice list 2>/dev/null | grep -q "/$ns/occlusion/step" && break; sleep 0.2; done
  done
  "$trainer" --out "$scratch/ros_2" --envs ros:/sim0,/sim1 --steps "$steps" >/dev/null 2>&1
  summarise "2 over ROS (same machine)" "$scratch/ros_2"
)
rm -rf "$scratch"
