#!/usr/bin/env bash
# Sets up bakegi on a fresh Debian 12 machine (as root): installs the Debian packages the
# build, the tests and Blender need, builds the core (Release), packs the add-on zip with
# the library inside, and installs + enables it in Blender's user preferences. (Blender 4.2,
# 4.5 and 5.0 for the tests come as Python modules: tools/setup_bpy.sh, run by run_tests.sh.)
#   BAKEGI_SKIP_APT=1  skip apt (packages already there)
#   BAKEGI_BUILD_DIR   build folder (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${BAKEGI_BUILD_DIR:-build}

packages=(cmake ninja-build g++ pkg-config
          libembree-dev libglm-dev libtbb-dev libopenexr-dev libeigen3-dev libboost-dev
          libmeshoptimizer-dev libcpp-httplib-dev libstb-dev zlib1g-dev
          googletest libgtest-dev libgmock-dev libbenchmark-dev
          clang  # libFuzzer (.ci/fuzz)
          blender python3 python3-numpy python3-matplotlib python3-venv python3-pytest xvfb xauth
          # what the bpy wheels of tools/setup_bpy.sh link to (ldd of bpy/__init__.so)
          libgl1 libsm6 libice6 libxxf86vm1 libxi6 libxkbcommon0 libxfixes3 libxrender1 libgomp1)

if [ "${BAKEGI_SKIP_APT:-0}" != 1 ]; then
  missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "== installing Debian packages: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq "${missing[@]}" >/dev/null
  fi
fi

echo "== building the core ($build_dir)"
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" -j2

echo "== building the web page (addon/web: three.js from npm, bundled into the add-on)"
# node and npm: the machine's own (the base image has Node 20), else Debian's.
if ! command -v npm >/dev/null; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq nodejs npm >/dev/null
fi
(cd addon/web && npm ci --no-audit --no-fund --loglevel=error --cache "$HOME/.cache/bakegi/npm" \
  && npm run build --silent) || { echo "building the web page failed"; exit 1; }

echo "== packing and installing the Blender add-on"
/usr/bin/python3 tools/make_addon_zip.py --build-dir "$build_dir" --out dist
zip=$(ls -t dist/bakegi-*.zip | head -n 1)
blender -b --factory-startup --python tools/install_addon.py -- "$zip" 2>&1 \
  | grep -E "^bakegi|Error|error" || true
blender -b --python-expr "import addon_utils, sys; \
loaded = addon_utils.check('bakegi')[1]; print('bakegi add-on enabled:', loaded); \
sys.exit(0 if loaded else 1)" 2>&1 | grep -E "bakegi add-on enabled" 
