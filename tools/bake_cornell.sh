#!/usr/bin/env bash
# The main job: set up, build the bundled Cornell box from scenes/, bake its indirect light
# with the installed add-on (its default bake: the path tracer to a 5% target error through
# its denoiser), save the .blend, render a PNG from its camera that shows the bake
# (albedo x (direct + baked indirect)), and print time and size figures.
#   BAKEGI_METHOD    empty (the default bake), antiradiance, pathtrace or meshless
#   BAKEGI_SAMPLES   samples per bake point for BAKEGI_METHOD=pathtrace (default 256)
#   BAKEGI_OUT       output folder (default: out)
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
out=${BAKEGI_OUT:-out}
samples=${BAKEGI_SAMPLES:-256}
method=${BAKEGI_METHOD:-}
mkdir -p "$out"

echo "== building the Cornell box scene"
blender -b --factory-startup --python scenes/cornell_box.py -- --out "$out/cornell_box.blend" \
  2>&1 | grep -E "^cornell|Error" || true

method_arguments=()
if [ -z "$method" ]; then
  echo "== baking indirect light (the default bake: pathtrace to 5% through the denoiser)"
elif [ "$method" = pathtrace ]; then
  echo "== baking indirect light (pathtrace, $samples samples per corner)"
  method_arguments=(--method pathtrace --samples "$samples")
else
  echo "== baking indirect light ($method)"
  method_arguments=(--method "$method")
fi
blender -b "$out/cornell_box.blend" --python tools/bake_and_render.py -- \
  "${method_arguments[@]}" --blend "$out/cornell_box_baked.blend" --png "$out/cornell_box_baked.png" \
  --report "$out/cornell_box_report.json" 2>&1 | grep -E "^(bakegi|  )" || true

test -s "$out/cornell_box_baked.png" && test -s "$out/cornell_box_baked.blend"
echo "== result: $out/cornell_box_baked.png, $out/cornell_box_baked.blend, $out/cornell_box_report.json"
