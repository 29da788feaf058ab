#!/usr/bin/env bash
# The main job on the embedded objects: renders three seeded scenes with occlusion_render and
# prints their occlusion figures. Images go to ${DEMO_OUT:-output/demo}/seed_<N>/.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
source build_ws/devel/setup.bash
out=${DEMO_OUT:-output/demo}
for seed in 1 2 3; do
  echo "== scene seed $seed =="
  build_ws/devel/lib/occlusion_env/occlusion_render --seed "$seed" --out "$out/seed_$seed"
done
echo "Open $out/seed_1/occlusion.png to see the occluded pixels (red) and each object's outline."
