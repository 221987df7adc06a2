"""Plain-Python tests of the add-on's bpy-free modules (no Blender): light units, lightmap
layout, error-check text, and the ctypes binding against the built library.

    python3 -m pytest python_tests            (tools/run_tests.sh runs it)

The library is $BAKEGI_LIBRARY, else build/libbakegi.so.
"""

import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))


@pytest.fixture(scope="session")
def native():
    path = os.environ.get("BAKEGI_LIBRARY") or os.path.join(ROOT, "build", "libbakegi.so")
    if not os.path.isfile(path):
        pytest.fail(f"no library at {path}: build it (tools/setup.sh) or set BAKEGI_LIBRARY")
    from bakegi import native as binding

    binding.load_library(path)
    return binding
