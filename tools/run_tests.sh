#!/usr/bin/env bash
# Sets up (tools/setup.sh) and runs every test: the native GoogleTest suite (Release), the
# same suite under AddressSanitizer + UBSan, and the tests inside real Blender: Debian's
# Blender 3.4 (blender_tests/, the UI test under Xvfb) and Blender 4.2 LTS, 4.5 LTS and 5.0
# as Python modules (tools/setup_bpy.sh; every test but the UI one). One line per Blender
# version, then one line "N passed, N failed, N skipped" over everything.
#   BAKEGI_BPY_VERSIONS="4.2.23"  run a part of the matrix ("" for Blender 3.4 alone)
set -uo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh || { echo "setup failed"; exit 1; }
build_dir=${BAKEGI_BUILD_DIR:-build}
results=$(mktemp -d)

echo "== native tests (Release)"
ctest --test-dir "$build_dir" --output-on-failure -j2 --output-junit "$results/native.xml"
native_rc=$?

echo "== native tests (AddressSanitizer + UBSan)"
BAKEGI_JUNIT="$results/asan.xml" bash .ci/asan
asan_rc=$?

echo "== tests in Blender"
/usr/bin/python3 blender_tests/run.py --library "$build_dir/libbakegi.so" --junit "$results/blender.xml" \
  | tee "$results/blender.log"
blender_rc=${PIPESTATUS[0]}
if [ "${BAKEGI_BPY_VERSIONS-all}" != "" ]; then
  if interpreters=$(bash tools/setup_bpy.sh); then
    while read -r version python; do
      /usr/bin/python3 blender_tests/run.py --library "$build_dir/libbakegi.so" --bpy "$python" \
        --junit "$results/blender-$version.xml" | tee -a "$results/blender.log"
      [ "${PIPESTATUS[0]}" -eq 0 ] || blender_rc=1
    done <<< "$interpreters"
  else
    echo "setting up the bpy versions failed"
    blender_rc=1
  fi
fi
echo "== Blender versions"
grep -E "^Blender [0-9.]+.*: [0-9]+ passed" "$results/blender.log"

if [ $native_rc -ne 0 ] || [ $asan_rc -ne 0 ] || [ $blender_rc -ne 0 ]; then
  echo "FAILED (exit codes: native $native_rc, asan $asan_rc, blender $blender_rc)"
  status=1
else
  status=0
fi
/usr/bin/python3 - "$results" <<'PY'
import glob, sys, xml.etree.ElementTree as ET
passed = failed = skipped = 0
for path in sorted(glob.glob(sys.argv[1] + "/*.xml")):
    root = ET.parse(path).getroot()
    suites = [root] if root.tag == "testsuite" else root.iter("testsuite")
    for s in suites:
        t, f, e, sk = (int(s.get(k, 0)) for k in ("tests", "failures", "errors", "skipped"))
        passed += t - f - e - sk; failed += f + e; skipped += sk
print("%d passed, %d failed, %d skipped" % (passed, failed, skipped))
PY
exit $status
