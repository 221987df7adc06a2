#!/usr/bin/env python3
"""Run the tests that live inside real Blender, each file in its own Blender process.

    python3 blender_tests/run.py --library build/libbakegi.so [--junit out.xml] [--output out/blender_tests]
    python3 blender_tests/run.py --installed            # use the add-on installed in Blender
    python3 blender_tests/run.py --library build/libbakegi.so --bpy ~/.cache/bakegi/bpy/4.2.23/bin/python

With --bpy the tests run in Blender as a Python module (the `bpy` package of that
interpreter, through blender_tests/bpy_boot.py) instead of the Blender program; the tests
that need a window (test_ui.py) are left out there.

With --library, a temporary user-scripts folder holds addons/bakegi (a link
to the repository's addon/bakegi) and BAKEGI_LIBRARY points at the library,
so nothing in the repository or in the user's Blender is changed. Each
blender_tests/test_*.py runs as

    blender -b --factory-startup --python-exit-code 1 --python <file>

(test_ui.py without -b, under ``xvfb-run -a``), runs its unittest cases and
writes their outcome to $BAKEGI_TEST_RESULTS. The last line printed is
``Blender <version>: N passed, N failed, N skipped``; the exit code is non-zero on any failure.
Plain Python 3, no dependencies.
"""

import argparse
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
UI_TESTS = ("test_ui.py",)  # need a real window (Xvfb) instead of background mode


def parse_arguments():
    parser = argparse.ArgumentParser(description="Run bakegi's tests inside Blender.")
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--library", help="path to libbakegi.so to use with the repository's add-on")
    source.add_argument("--installed", action="store_true", help="use the bakegi add-on installed in Blender")
    program = parser.add_mutually_exclusive_group()
    program.add_argument("--blender", default=shutil.which("blender") or "blender",
                         help="the Blender program (default: blender on PATH)")
    program.add_argument("--bpy", metavar="PYTHON",
                         help="a Python interpreter with the bpy module: run the tests in it instead")
    parser.add_argument("--junit", help="write JUnit XML here")
    parser.add_argument("--output", default=os.path.join(ROOT, "out", "blender_tests"),
                        help="folder for files the tests make for people (screenshots)")
    parser.add_argument("--timeout", type=float, default=900.0, help="seconds per test file")
    parser.add_argument("tests", nargs="*", help="test files or names (default: all test_*.py)")
    return parser.parse_args()


def select_tests(names, bpy_module=False):
    every = sorted(glob.glob(os.path.join(HERE, "test_*.py")))
    if bpy_module:  # no window in the bpy module
        every = [p for p in every if os.path.basename(p) not in UI_TESTS]
    if not names:
        return every
    chosen = []
    for name in names:
        base = os.path.basename(name)
        if not base.endswith(".py"):
            base = base + ".py"
        if not base.startswith("test_"):
            base = "test_" + base
        path = os.path.join(HERE, base)
        if path not in every:
            sys.exit(f"run.py: no test file {base}")
        chosen.append(path)
    return chosen


def prepare_environment(arguments, scratch):
    env = dict(os.environ)
    env["BAKEGI_TEST_OUTPUT"] = os.path.abspath(arguments.output)
    env["BAKEGI_REPO"] = ROOT
    # Temporary files of the tests and of Blender itself (its session folders, which a
    # bpy process leaves behind) go in the scratch folder, removed after the run.
    temporary = os.path.join(scratch, "tmp")
    os.makedirs(temporary, exist_ok=True)
    env["TMPDIR"] = temporary
    if arguments.library:
        library = os.path.abspath(arguments.library)
        if not os.path.isfile(library):
            sys.exit(f"run.py: library not found: {library}")
        scripts = os.path.join(scratch, "scripts")
        os.makedirs(os.path.join(scripts, "addons"))
        os.symlink(os.path.join(ROOT, "addon", "bakegi"), os.path.join(scripts, "addons", "bakegi"))
        env["BLENDER_USER_SCRIPTS"] = scripts
        # What the add-on writes for unsaved files stays in the scratch folder too.
        env["BLENDER_USER_DATAFILES"] = os.path.join(scratch, "datafiles")
        env["BLENDER_USER_EXTENSIONS"] = os.path.join(scratch, "extensions")
        env["BAKEGI_LIBRARY"] = library
    # Keep Blender's own config (and an installed add-on's preferences) out of a --library run.
    env.setdefault("PYTHONDONTWRITEBYTECODE", "1")
    return env


def command_for(arguments, path):
    name = os.path.basename(path)
    if arguments.bpy:
        return [arguments.bpy, os.path.join(HERE, "bpy_boot.py"), path]
    if name in UI_TESTS:
        return ["xvfb-run", "-a", "-s", "-screen 0 1024x768x24", arguments.blender, "--factory-startup",
                "--enable-event-simulate", "-p", "0", "0", "800", "600", "--python-exit-code", "1", "--python", path]
    return [arguments.blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python", path]


def run_one(arguments, path, env, scratch):
    name = os.path.splitext(os.path.basename(path))[0]
    results = os.path.join(scratch, name + ".json")
    env = dict(env, BAKEGI_TEST_RESULTS=results)
    log_path = os.path.join(scratch, name + ".log")
    start = time.perf_counter()
    with open(log_path, "w") as log:
        try:
            process = subprocess.run(command_for(arguments, path), env=env, stdout=log, stderr=subprocess.STDOUT,
                                     timeout=arguments.timeout, cwd=ROOT)
            code = process.returncode
        except subprocess.TimeoutExpired:
            code = "timeout"
    seconds = time.perf_counter() - start
    summary = None
    if os.path.isfile(results):
        with open(results) as f:
            summary = json.load(f)
    if summary is None or (code != 0 and summary["failures"] + summary["errors"] == 0):
        # Blender died, timed out or exited badly before or after reporting: one error for the file.
        with open(log_path, errors="replace") as f:
            tail = f.read()[-4000:]
        cases = (summary or {}).get("cases", [])
        cases.append({"name": name, "status": "error", "seconds": round(seconds, 2),
                      "message": f"Blender exited with {code}; log tail:\n{tail}"})
        summary = {"cases": cases}
    summary["file_seconds"] = seconds
    summary["log"] = log_path
    return name, summary


def write_junit(path, results):
    suites = ET.Element("testsuites")
    for name, summary in results:
        cases = summary["cases"]
        suite = ET.SubElement(suites, "testsuite", name=f"blender.{name}", tests=str(len(cases)),
                              failures=str(sum(c["status"] == "failed" for c in cases)),
                              errors=str(sum(c["status"] == "error" for c in cases)),
                              skipped=str(sum(c["status"] == "skipped" for c in cases)),
                              time=f"{summary['file_seconds']:.2f}")
        for case in cases:
            element = ET.SubElement(suite, "testcase", classname=f"blender.{name}", name=case["name"],
                                    time=str(case["seconds"]))
            if case["status"] in ("failed", "error"):
                tag = "failure" if case["status"] == "failed" else "error"
                ET.SubElement(element, tag, message=case["message"].splitlines()[-1][:200] if case["message"] else "")
                element[-1].text = case["message"]
            elif case["status"] == "skipped":
                ET.SubElement(element, "skipped", message=case["message"])
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    ET.ElementTree(suites).write(path, encoding="utf-8", xml_declaration=True)


def blender_version(arguments):
    """'Blender 4.2.23 (bpy module)' or 'Blender 3.4.1' for the report lines."""
    if arguments.bpy:
        command = [arguments.bpy, "-c", "import bpy; print(bpy.app.version_string)"]
    else:
        command = [arguments.blender, "-b", "--factory-startup", "--python-expr",
                   "import bpy; print('VERSION', bpy.app.version_string)"]
    try:
        out = subprocess.run(command, capture_output=True, text=True, timeout=120).stdout
    except (OSError, subprocess.TimeoutExpired) as error:
        sys.exit(f"run.py: cannot start {command[0]}: {error}")
    lines = [l for l in out.splitlines() if l.strip()]
    if arguments.bpy:
        return f"Blender {lines[-1].strip() if lines else '?'} (bpy module)"
    found = [l.split(None, 1)[1] for l in lines if l.startswith("VERSION ")]
    return f"Blender {found[0] if found else '?'}"


def main():
    arguments = parse_arguments()
    tests = select_tests(arguments.tests, bool(arguments.bpy))
    version = blender_version(arguments)
    print(f"== tests in {version}", flush=True)
    os.makedirs(arguments.output, exist_ok=True)
    scratch = tempfile.mkdtemp(prefix="bakegi_blender_tests_")
    env = prepare_environment(arguments, scratch)
    results = []
    counts = {"passed": 0, "failed": 0, "skipped": 0}
    for path in tests:
        name, summary = run_one(arguments, path, env, scratch)
        results.append((name, summary))
        for case in summary["cases"]:
            status = {"error": "failed"}.get(case["status"], case["status"])
            counts[status] += 1
            line = f"  {case['status'].upper():7s} {case['name']} ({case['seconds']:.1f} s)"
            print(line)
            if case["status"] in ("failed", "error"):
                print("    " + case["message"].replace("\n", "\n    ").rstrip())
        print(f"{name}: {summary['file_seconds']:.1f} s (log: {summary['log']})", flush=True)
    if arguments.junit:
        write_junit(arguments.junit, results)
    print(f"{version}: {counts['passed']} passed, {counts['failed']} failed, {counts['skipped']} skipped")
    if not counts["failed"]:
        shutil.rmtree(scratch, ignore_errors=True)  # the logs are kept only where a test failed
    return 1 if counts["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
