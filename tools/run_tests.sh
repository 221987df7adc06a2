#!/usr/bin/env bash
# Sets up (tools/setup.sh) and runs every test: the native GoogleTest suite (Release), the
# add-on's bpy-free modules under pytest (python_tests/, no Blender), the native suite under
# AddressSanitizer + UBSan, the readers under libFuzzer (.ci/fuzz, 15 s per fuzzer), and the
# tests inside real Blender: Debian's
# Blender 3.4 (blender_tests/, the UI test under Xvfb) and Blender 4.2 LTS, 4.5 LTS and 5.0
# as Python modules (tools/setup_bpy.sh; every test but the UI one). One line per Blender
# version, then one line "N passed, N failed, N skipped" over everything.
# Then the web page in Debian's Chromium (tools/web_test.py: Blender exports and renders the
# Cornell box, playwright-core streams it from `bakegi serve`).
# Last, the portable library: built on Debian 11 with its dependencies beside it, loaded and
# baking the Cornell box in a clean Debian 11 root (tools/build_portable.sh, check_portable.sh),
# then its zip installed in each Blender version (test_install with BAKEGI_INSTALL_ZIP).
#   BAKEGI_BPY_VERSIONS="4.2.23"  run a part of the matrix ("" for Blender 3.4 alone)
#   BAKEGI_SKIP_PORTABLE=1        leave out the portable library
set -uo pipefail
cd "$(dirname "$0")/.."
# Seconds per stage, printed at the end: CI must stay under 45 minutes (docs/testing.md).
timings=()
stage_name="setup (Debian packages, the Release build, the web page, the add-on)"
stage_started=$(date +%s)
stage() {  # ends the running stage and starts the next
  local now
  now=$(date +%s)
  timings+=("$(printf '%5d s  %s' $((now - stage_started)) "$stage_name")")
  stage_name=$1
  stage_started=$now
  echo "== $1"
}
bash tools/setup.sh || { echo "setup failed"; exit 1; }
build_dir=${BAKEGI_BUILD_DIR:-build}
results=$(mktemp -d)

stage "native tests (Release)"
ctest --test-dir "$build_dir" --output-on-failure -j2 --output-junit "$results/native.xml"
native_rc=$?

stage "add-on tests without Blender (pytest: bpy-free modules and the ctypes binding)"
BAKEGI_LIBRARY="$build_dir/libbakegi.so" PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 -m pytest -q \
  -p no:cacheprovider python_tests --junitxml "$results/python.xml"
python_rc=$?

stage "native tests (AddressSanitizer + UBSan, their build included)"
BAKEGI_JUNIT="$results/asan.xml" bash .ci/asan
asan_rc=$?

stage "fuzzers (libFuzzer with ASan + UBSan on the readers: .ci/fuzz, their build included)"
BAKEGI_JUNIT="$results/fuzz.xml" BAKEGI_BUILD_DIR="$build_dir" bash .ci/fuzz
fuzz_rc=$?

stage "tests in Blender (the bpy modules' download included)"
/usr/bin/python3 blender_tests/run.py --library "$build_dir/libbakegi.so" --junit "$results/blender.xml" \
  | tee "$results/blender.log"
blender_rc=${PIPESTATUS[0]}
if [ "${BAKEGI_BPY_VERSIONS-all}" != "" ]; then
  if interpreters=$(bash tools/setup_bpy.sh); then
    while read -r version python; do
      /usr/bin/python3 blender_tests/run.py --library "$build_dir/libbakegi.so" --bpy "$python" \
        --junit "$results/blender-$version.xml" < /dev/null | tee -a "$results/blender.log"
      [ "${PIPESTATUS[0]}" -eq 0 ] || blender_rc=1
    done <<< "$interpreters"
  else
    echo "setting up the bpy versions failed"
    blender_rc=1
  fi
fi
echo "== Blender versions"
grep -E "^Blender [0-9.]+.*: [0-9]+ passed" "$results/blender.log"

stage "the web page in Chromium"
if ! command -v chromium >/dev/null; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
fi
/usr/bin/python3 tools/web_test.py --work out/web_tests --build "$build_dir" \
  --junit "$results/web.xml" > "$results/web.log" 2>&1
web_rc=$?
grep -E "^(ok  |FAIL)|WEB " "$results/web.log"
[ $web_rc -eq 0 ] || tail -n 40 "$results/web.log"

portable_rc=0
if [ "${BAKEGI_SKIP_PORTABLE:-0}" != 1 ]; then
  stage "portable library (built on Debian 11, loaded in a clean Debian 11 root)"
  { bash tools/build_portable.sh && bash tools/check_portable.sh; } > "$results/portable.log" 2>&1
  portable_rc=$?
  grep -E "newest glibc|loaded|NRMSE|PORTABLE OK|glibc of|check_portable:|build_portable:" "$results/portable.log"
  [ $portable_rc -eq 0 ] || tail -n 30 "$results/portable.log"
  /usr/bin/python3 - "$results/portable.xml" "$portable_rc" "$(( $(date +%s) - stage_started ))" "$results/portable.log" <<'PY'
import sys, xml.etree.ElementTree as ET
path, rc, seconds, log = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
suite = ET.Element("testsuite", name="portable", tests="1", failures=str(int(rc != 0)), errors="0",
                   skipped="0", time=seconds)
case = ET.SubElement(suite, "testcase", classname="portable", name="loads_and_bakes_in_a_clean_root",
                     time=seconds)
if rc:
    ET.SubElement(case, "failure", message="see the portable log").text = open(log, errors="replace").read()[-4000:]
ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)
PY
  # The same zip installed the way each version installs it, its library loaded next to
  # that version's own TBB and OpenEXR (test_install with BAKEGI_INSTALL_ZIP).
  zip=$(ls dist/bakegi-*-portable.zip 2>/dev/null | head -n 1)
  if [ $portable_rc -eq 0 ] && [ -n "$zip" ]; then
    stage "portable zip installed in each Blender version"
    BAKEGI_INSTALL_ZIP="$zip" /usr/bin/python3 blender_tests/run.py --library "$build_dir/libbakegi.so" \
      --junit "$results/portable-install.xml" test_install < /dev/null > "$results/portable-install.log" 2>&1 \
      || portable_rc=1
    while read -r version python; do
      [ -n "$python" ] || continue
      BAKEGI_INSTALL_ZIP="$zip" /usr/bin/python3 blender_tests/run.py --library "$build_dir/libbakegi.so" \
        --bpy "$python" --junit "$results/portable-install-$version.xml" test_install < /dev/null \
        >> "$results/portable-install.log" 2>&1 || portable_rc=1
    done <<< "${interpreters:-}"
    grep -E "^Blender [0-9.]+.*: [0-9]+ passed" "$results/portable-install.log"
    [ $portable_rc -eq 0 ] || tail -n 40 "$results/portable-install.log"
  fi
fi

stage "time per stage"
printf "%s\n" "${timings[@]}"

if [ $native_rc -ne 0 ] || [ $python_rc -ne 0 ] || [ $asan_rc -ne 0 ] || [ $fuzz_rc -ne 0 ] || [ $blender_rc -ne 0 ] || [ $web_rc -ne 0 ] || [ $portable_rc -ne 0 ]; then
  echo "FAILED (exit codes: native $native_rc, python $python_rc, asan $asan_rc, fuzz $fuzz_rc, blender $blender_rc, web $web_rc, portable $portable_rc)"
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
