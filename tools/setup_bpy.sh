#!/usr/bin/env bash
# Creates one Python virtual environment per Blender version of the test matrix, each with
# Blender as a Python module (the `bpy` package from the Python package index, built for
# Python 3.11, Debian 12's python3). Prints the interpreters, one per line, as
#   <version> <path to python>
# Environments live in $BAKEGI_BPY_DIR (default ~/.cache/bakegi/bpy) and are reused while
# they import the pinned version; wheels are cached in $BAKEGI_PIP_CACHE (default
# ~/.cache/bakegi/pip). Both are caches: deleting them costs a download (~370 MB per version).
# Blender 5.1 and later need Python 3.13, which Debian 12 does not have.
set -euo pipefail

# The matrix: Blender 4.2 LTS, 4.5 LTS and 5.0, pinned to exact releases.
BPY_VERSIONS=(${BAKEGI_BPY_VERSIONS:-4.2.23 4.5.15 5.0.1})
root=${BAKEGI_BPY_DIR:-$HOME/.cache/bakegi/bpy}
pip_cache=${BAKEGI_PIP_CACHE:-$HOME/.cache/bakegi/pip}
python=/usr/bin/python3

if ! "$python" -c "import venv, ensurepip" 2>/dev/null; then
  echo "setup_bpy: python3-venv is missing (apt-get install python3-venv)" >&2
  exit 1
fi
mkdir -p "$root" "$pip_cache"
for version in "${BPY_VERSIONS[@]}"; do
  env_dir="$root/$version"
  interpreter="$env_dir/bin/python"
  if [ -x "$interpreter" ] && [ "$("$interpreter" -c 'import bpy; print(".".join(map(str, bpy.app.version)))' 2>/dev/null | tail -n 1)" = "$version" ]; then
    echo "$version $interpreter"
    continue
  fi
  echo "setup_bpy: creating $env_dir (bpy==$version)" >&2
  rm -rf "$env_dir"
  "$python" -m venv "$env_dir"
  "$env_dir/bin/pip" install --quiet --disable-pip-version-check --cache-dir "$pip_cache" "bpy==$version" >&2
  found=$("$interpreter" -c 'import bpy; print(".".join(map(str, bpy.app.version)))' 2>/dev/null | tail -n 1)
  if [ "$found" != "$version" ]; then
    echo "setup_bpy: bpy==$version installed but imports as '$found'" >&2
    exit 1
  fi
  echo "$version $interpreter"
done
