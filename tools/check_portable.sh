#!/usr/bin/env bash
# Proves that the portable zip (tools/build_portable.sh) carries what it needs: in a clean
# Debian 11 root (glibc 2.31) that has Python and NumPy but none of the build's -dev packages
# nor Embree, TBB or OpenEXR, the zip's own library is loaded through the add-on's bpy-free
# native.py and bakes the Cornell box (antiradiance, no noise); the result must match the
# Debian 12 build's bake of the same scene file.
#   BAKEGI_CLEAN_ROOT  the clean root (default ~/.cache/bakegi/bullseye-clean; made once)
# As root. Needs build/ (the Debian 12 build, for the scene export and the comparison).
set -euo pipefail
cd "$(dirname "$0")/.."
root=${BAKEGI_CLEAN_ROOT:-$HOME/.cache/bakegi/bullseye-clean}
mirror=${BAKEGI_DEBIAN_MIRROR:-http://deb.debian.org/debian}
zip=$(ls -t dist/bakegi-*-portable.zip 2>/dev/null | head -n 1)
[ -n "$zip" ] || { echo "check_portable: no dist/*-portable.zip: run tools/build_portable.sh" >&2; exit 1; }

if [ ! -x "$root/usr/bin/python3" ]; then
  echo "== making the clean Debian 11 root $root"
  rm -rf "$root"
  debootstrap --variant=minbase --include=python3,python3-numpy bullseye "$root" "$mirror" >/dev/null
fi
if chroot "$root" dpkg -l | grep -E '^ii +(libembree|libtbb|libopenexr|libilmbase|[a-z0-9.+-]+-dev) '; then
  echo "check_portable: the clean root has the packages above; it must not" >&2
  exit 1
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "== exporting the Cornell box and baking it with the Debian 12 build"
/usr/bin/python3 tools/export_scene.py --scene cornell_box --out "$work/cornell.bgs" --build build >/dev/null
build/bakegi bake "$work/cornell.bgs" --method antiradiance --out "$work/debian12.npy" >/dev/null

echo "== loading $zip in the clean root and baking there"
rm -rf "$root/opt/bakegi_check"
mkdir -p "$root/opt/bakegi_check"
/usr/bin/python3 -c "import zipfile, sys; zipfile.ZipFile(sys.argv[1]).extractall(sys.argv[2])" \
  "$zip" "$root/opt/bakegi_check"
cp "$work/cornell.bgs" "$work/debian12.npy" "$root/opt/bakegi_check/"
cat > "$root/opt/bakegi_check/check.py" <<'PY'
import sys
import numpy as np
sys.path.insert(0, "/opt/bakegi_check")
from bakegi import native  # bpy-free: ctypes and NumPy only
native.load_library()
print("loaded", native.default_library_path(), native.version_string())
scene, points = native.Scene.read("/opt/bakegi_check/cornell.bgs")
job = native.Job(scene, points, native.Settings(method="antiradiance"))
job.wait()
values = job.result().astype(np.float64)
reference = np.load("/opt/bakegi_check/debian12.npy").astype(np.float64)
y = values @ [0.2126, 0.7152, 0.0722]
r = reference @ [0.2126, 0.7152, 0.0722]
nrmse = float(np.sqrt(np.mean((y - r) ** 2)) / r.mean())
print(f"{len(values)} bake points, mean {y.mean():.6f} (Debian 12 build {r.mean():.6f}), "
      f"NRMSE against it {100 * nrmse:.4f}%")
assert np.isfinite(values).all() and y.mean() > 0
assert nrmse < 0.01, "the portable library bakes differently"
print("PORTABLE OK")
PY
chroot "$root" /usr/bin/python3 /opt/bakegi_check/check.py
echo "glibc of the clean root: $(chroot "$root" ldd --version | head -n 1)"
