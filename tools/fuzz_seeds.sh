#!/usr/bin/env bash
# The fuzzers' seed corpus, exported from the project's scenes: the Cornell box (one grid
# cell per wall, so that the files are kilobytes) as a .bgs with corner bake points and as
# a .bgs + .bgl lightmap layout (Blender 3.4 and the add-on, tools/export_scene.py), its
# meshless and antiradiance cache files (the CLI baking with --cache-dir at coarse
# settings), the web export's visibility volume of a 2^3 grid of it, and the settings of
# docs/settings.md's examples as key=value text.
#   tools/fuzz_seeds.sh OUT [BUILD]   OUT/<fuzzer>/ per fuzzer; BUILD: a Release build (build)
set -euo pipefail
cd "$(dirname "$0")/.."
out=$1
build=${2:-build}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"/{scene_file,layout_file,cache_file,settings,visibility_file}

/usr/bin/python3 tools/export_scene.py --scene cornell_box --out "$work/corners.bgs" \
  --build "$build" -- --subdivisions 1 > "$work/export.log" 2>&1 \
  || { tail -n 20 "$work/export.log"; exit 1; }
/usr/bin/python3 tools/export_scene.py --scene cornell_box --out "$work/texels.bgs" \
  --build "$build" --target LIGHTMAP --texels-per-meter 3 -- --subdivisions 1 \
  > "$work/export.log" 2>&1 || { tail -n 20 "$work/export.log"; exit 1; }
cp "$work/corners.bgs" "$work/texels.bgs" "$out/scene_file/"
cp "$work/texels.bgl" "$out/layout_file/"

"$build/bakegi" bake "$work/corners.bgs" --out "$work/m.npy" --method meshless --set levels=1 \
  --set gather_rays=4 --set error_probes=0 --cache-dir "$work/cache" > /dev/null 2>&1
"$build/bakegi" bake "$work/corners.bgs" --out "$work/a.npy" --method antiradiance \
  --set bins=12 --set patch_size=2 --set near_field_rays=0 --set error_probes=0 \
  --cache-dir "$work/cache" > /dev/null 2>&1
cp "$work"/cache/*.bgcache "$out/cache_file/"

# The web page's visibility volume: a 2 x 2 x 2 grid of the box, exported for the web.
"$build/bakegi" grid bake "$work/corners.bgs" --out "$work/g.bgivg" --cell 1 --rays 4 \
  > /dev/null 2>&1
"$build/bakegi" web export "$work/corners.bgs" --grid "$work/g.bgivg" --out "$work/site" \
  > /dev/null 2>&1
cp "$work/site/grid_visibility.bin" "$out/visibility_file/"

printf 'method=pathtrace\nsamples=64\ndenoise=1\ntarget_error=0.05\n' > "$out/settings/pathtrace"
printf 'method=antiradiance\nbins=12\npatch_size=2\nscheme=asymmetric\n' > "$out/settings/antiradiance"
printf 'method=meshless\nlevels=1\ngather_rays=4\nviewpoint=0,1,2\ncache_dir=//c\n' \
  > "$out/settings/meshless"
printf 'method=splatting\nvpl_count=64\nrefinement=illumination\ndepth_threshold=0.1\n' \
  > "$out/settings/splatting"
printf 'method=grid\nthreads=2\nmemory_budget_mb=256\n' > "$out/settings/grid"
echo "fuzz_seeds: $(find "$out" -type f | wc -l) seeds in $out"
