"""Helpers shared by the tests that run inside Blender (imported from test_*.py).

Each test file is a unittest module that blender_tests/run.py starts in its own
Blender process. ``run_tests(module)`` runs its TestCases, writes the outcome
as JSON to $BAKEGI_TEST_RESULTS (the runner reads it) and exits Blender with
a non-zero code on any failure.
"""

import json
import os
import sys
import time
import traceback
import unittest
import warnings

import bpy
import numpy

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DATA = os.path.join(HERE, "data")
for path in (HERE, os.path.join(ROOT, "scenes"), os.path.join(ROOT, "tools")):
    if path not in sys.path:
        sys.path.insert(0, path)

ATTRIBUTE = "BakeGI_Indirect"


def output_dir():
    """Where tests put files meant for people (screenshots): $BAKEGI_TEST_OUTPUT or a temp dir."""
    path = os.environ.get("BAKEGI_TEST_OUTPUT") or os.path.join(bpy.app.tempdir or "/tmp", "bakegi_test_output")
    os.makedirs(path, exist_ok=True)
    return path


def blender_script_command(script, arguments=()):
    """The command that runs `script` in a fresh background Blender of this same version:
    the Blender program, or (in Blender as a Python module, which has no program) this
    Python through bpy_boot.py. What follows "--" in sys.argv is `arguments`."""
    if bpy.app.binary_path:
        return [bpy.app.binary_path, "-b", "--factory-startup", "--python-exit-code", "1", "--python", script,
                "--", *arguments]
    return [sys.executable, os.path.join(HERE, "bpy_boot.py"), script, "--", *arguments]


def enable_addon():
    """Enable the bakegi add-on (found through BLENDER_USER_SCRIPTS or the user's add-ons); return the module."""
    import addon_utils

    module = addon_utils.enable("bakegi", default_set=True, handle_error=None)
    if module is None:
        raise RuntimeError("the bakegi add-on could not be enabled (is it installed or on BLENDER_USER_SCRIPTS?)")
    import bakegi

    return bakegi


def new_empty_scene():
    """Clear the current scene's objects and data (no factory reset: it would disable the add-on)."""
    import cornell_box

    cornell_box.clear_scene()
    return bpy.context.scene


class AddonCase(unittest.TestCase):
    """An empty scene and the add-on enabled once per class, as cls.bakegi."""

    @classmethod
    def setUpClass(cls):
        new_empty_scene()
        cls.bakegi = enable_addon()


class SmallCornellCase(AddonCase):
    """AddonCase with a fresh small Cornell box (cornell_box.TEST_SUBDIVISIONS) before every
    test, as self.objects (name -> object)."""

    def setUp(self):
        import cornell_box
        new_empty_scene()
        self.objects = cornell_box.build_cornell_box(cornell_box.TEST_SUBDIVISIONS)


def node_material(name, kind, socket="Surface"):
    """A material whose output's `socket` (Surface, Volume) is fed by one new shader node of
    `kind`, and nothing else; returns (material, node)."""
    import cornell_box  # scenes/: use_nodes for every version
    material = bpy.data.materials.new(name)
    cornell_box.use_nodes(material)
    nodes = material.node_tree.nodes
    for node in list(nodes):
        if node.type != "OUTPUT_MATERIAL":
            nodes.remove(node)
    output = next(n for n in nodes if n.type == "OUTPUT_MATERIAL")
    shader = nodes.new(kind)
    material.node_tree.links.new(shader.outputs[0], output.inputs[socket])
    return material, shader

def reference_folder(version=None):
    """blender_tests/data/<major.minor>/: the Cycles references of this Blender version (Cycles'
    results differ between versions: each version's bakes are compared with its own)."""
    major, minor = (version or bpy.app.version)[:2]
    return os.path.join(DATA, f"{major}.{minor}")


def load_reference(name):
    """(values (n, 3) float64, sidecar dict) of blender_tests/data/<version>/<name>.npy/.json."""
    folder = reference_folder()
    path = os.path.join(folder, name + ".npy")
    if not os.path.isfile(path):
        raise AssertionError(
            f"no Cycles reference {name} for Blender {bpy.app.version_string} in {folder}: make them with "
            "blender_tests/make_references.py in this version")
    values = numpy.load(path).astype(numpy.float64)
    with open(os.path.join(folder, name + ".json")) as f:
        sidecar = json.load(f)
    if tuple(int(x) for x in sidecar["blender"].split(".")[:2]) != tuple(bpy.app.version[:2]):
        raise AssertionError(f"{path} was made with Blender {sidecar['blender']}, not {bpy.app.version_string}")
    return values, sidecar


def read_color_attribute(objects, name=ATTRIBUTE, domain=None):
    """Concatenated (n, 3) float64 RGB of a colour attribute over `objects` (names or objects), in order."""
    arrays = []
    for obj in objects:
        obj = bpy.data.objects[obj] if isinstance(obj, str) else obj
        mesh = obj.data
        attribute = mesh.color_attributes.get(name)
        if attribute is None:
            raise AssertionError(f"{obj.name} has no colour attribute {name!r}")
        if domain is not None and attribute.domain != domain:
            raise AssertionError(f"{obj.name}: {name} is on domain {attribute.domain}, expected {domain}")
        rgba = numpy.empty(len(attribute.data) * 4, dtype=numpy.float32)
        attribute.data.foreach_get("color", rgba)
        arrays.append(rgba.reshape(-1, 4)[:, :3])
    return numpy.concatenate(arrays).astype(numpy.float64)


def scene_snapshot():
    """Everything a bake may touch, as plain data: attributes of every mesh (names,
    domains, types, a checksum of their values, the active/render colour), every
    material's node tree (nodes, their inputs' values, links), object names and
    data-block counts."""
    import cornell_box

    snapshot = {"counts": {}, "meshes": {}, "materials": {}, "objects": sorted(o.name for o in bpy.data.objects)}
    for collection in ("meshes", "materials", "node_groups", "images", "objects", "lights", "worlds"):
        snapshot["counts"][collection] = len(getattr(bpy.data, collection))
    for mesh in bpy.data.meshes:
        attributes = {}
        for attribute in mesh.attributes:
            if attribute.name.startswith(UI_STATE_PREFIXES):
                continue  # read through the elements' flags below
            attributes[attribute.name] = (attribute.domain, attribute.data_type, _attribute_checksum(attribute))
        colors = mesh.color_attributes
        snapshot["meshes"][mesh.name] = {
            "attributes": attributes,
            "active_color": colors.active_color_name,
            "render_color_index": colors.render_color_index,
            "materials": [m.name if m else None for m in mesh.materials],
            "vertices": len(mesh.vertices),
            "flags": _selection_and_visibility(mesh),
        }
    for material in bpy.data.materials:
        snapshot["materials"][material.name] = _node_tree_snapshot(material.node_tree) if cornell_box.uses_nodes(material) else None
    return snapshot


# Selection and visibility live in hidden attributes whose presence and type vary between
# Blender versions (absent = all false; 5.0's from_pydata even makes .select_edge INT32_2D):
# compared as the elements' flags, not as attributes.
UI_STATE_PREFIXES = (".select_", ".hide_", ".uv_select_")


def _selection_and_visibility(mesh):
    flags = {}
    for name in ("vertices", "edges", "polygons"):
        elements = getattr(mesh, name)
        for flag in ("select", "hide"):
            values = [False] * len(elements)
            elements.foreach_get(flag, values)
            flags[f"{name}.{flag}"] = sum(i for i, v in enumerate(values) if v)
    return flags


def _attribute_checksum(attribute):
    field = {"FLOAT_COLOR": "color", "BYTE_COLOR": "color", "FLOAT_VECTOR": "vector", "FLOAT2": "vector",
             "INT32_2D": "value", "QUATERNION": "value", "FLOAT4X4": "value"}.get(attribute.data_type, "value")
    width = {"FLOAT_COLOR": 4, "BYTE_COLOR": 4, "FLOAT_VECTOR": 3, "FLOAT2": 2, "INT32_2D": 2,
             "QUATERNION": 4, "FLOAT4X4": 16}.get(attribute.data_type, 1)
    try:
        values = numpy.empty(len(attribute.data) * width, dtype=numpy.float64)
        attribute.data.foreach_get(field, values)
        return round(float(numpy.nansum(values)), 6), len(attribute.data)
    except (TypeError, AttributeError, RuntimeError):
        return None, len(attribute.data)


def _socket_value(socket):
    value = getattr(socket, "default_value", None)
    if value is None:
        return None
    try:
        return tuple(round(float(x), 6) for x in value)
    except TypeError:
        return round(float(value), 6) if isinstance(value, (int, float)) else str(value)


def _node_tree_snapshot(tree):
    nodes = {}
    for node in tree.nodes:
        nodes[node.name] = (
            node.bl_idname,
            tuple((s.identifier, _socket_value(s)) for s in node.inputs),
            getattr(node, "attribute_name", None),
            getattr(node, "node_tree", None) and node.node_tree.name,
        )
    links = sorted(
        (l.from_node.name, l.from_socket.identifier, l.to_node.name, l.to_socket.identifier) for l in tree.links
    )
    return {"nodes": nodes, "links": links}


def snapshot_difference(before, after):
    """A readable list of what differs between two scene_snapshot()s (empty when equal)."""
    differences = []

    def walk(a, b, path):
        if isinstance(a, dict) and isinstance(b, dict):
            for key in sorted(set(a) | set(b), key=str):
                if key not in a:
                    differences.append(f"{path}/{key}: added")
                elif key not in b:
                    differences.append(f"{path}/{key}: removed")
                else:
                    walk(a[key], b[key], f"{path}/{key}")
        elif a != b:
            differences.append(f"{path}: {a!r} -> {b!r}")

    walk(before, after, "")
    return differences


class _JsonResult(unittest.TextTestResult):
    """Records every test's outcome and duration."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.cases = []
        self._started = {}

    def startTest(self, test):
        self._started[test.id()] = time.perf_counter()
        super().startTest(test)

    def _record(self, test, status, message="", name=None):
        seconds = time.perf_counter() - self._started.get(test.id(), time.perf_counter())
        self.cases.append({"name": name or test.id(), "status": status, "seconds": round(seconds, 3),
                           "message": message})

    def addSubTest(self, test, subtest, err):
        # A test whose subtests fail gets neither addSuccess nor addFailure: without this its
        # failures would vanish from the count.
        super().addSubTest(test, subtest, err)
        if err is not None:
            status = "failed" if issubclass(err[0], test.failureException) else "error"
            self._record(test, status, self._exc_info_to_string(err, test), name=subtest.id())

    def addSuccess(self, test):
        super().addSuccess(test)
        self._record(test, "passed")

    def addFailure(self, test, err):
        super().addFailure(test, err)
        self._record(test, "failed", self._exc_info_to_string(err, test))

    def addError(self, test, err):
        super().addError(test, err)
        self._record(test, "error", self._exc_info_to_string(err, test))

    def addSkip(self, test, reason):
        super().addSkip(test, reason)
        self._record(test, "skipped", reason)

    def addExpectedFailure(self, test, err):
        super().addExpectedFailure(test, err)
        self._record(test, "passed")

    def addUnexpectedSuccess(self, test):
        super().addUnexpectedSuccess(test)
        self._record(test, "failed", "unexpected success")


def write_results(cases, seconds):
    path = os.environ.get("BAKEGI_TEST_RESULTS")
    summary = {
        "tests": len(cases),
        "failures": sum(c["status"] == "failed" for c in cases),
        "errors": sum(c["status"] == "error" for c in cases),
        "skipped": sum(c["status"] == "skipped" for c in cases),
        "seconds": round(seconds, 2),
        "cases": cases,
    }
    if path:
        with open(path, "w") as f:
            json.dump(summary, f, indent=1)
    return summary


def _deprecated_api_use(caught, module_name):
    """One failed case if the add-on itself used an API this Blender deprecates (5.0 deprecated
    use_nodes, for one): such differences belong in addon/bakegi/compat.py."""
    found = sorted({f"{os.path.basename(w.filename)}:{w.lineno}: {w.message}" for w in caught
                    if issubclass(w.category, DeprecationWarning)
                    and os.path.basename(os.path.dirname(w.filename)) == "bakegi"})
    if not found:
        return []
    print("deprecated API used by the add-on:\n" + "\n".join(found))
    return [{"name": f"{module_name}.deprecated_api_in_the_add_on", "status": "failed", "seconds": 0.0,
             "message": f"the add-on uses APIs Blender {bpy.app.version_string} deprecates:\n" + "\n".join(found)}]


def run_tests(module_name):
    """Run the TestCases of `module_name` (a loaded module), report, and exit Blender."""
    start = time.perf_counter()
    try:
        suite = unittest.defaultTestLoader.loadTestsFromModule(sys.modules[module_name])
        runner = unittest.TextTestRunner(stream=sys.stdout, verbosity=2, resultclass=_JsonResult)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", DeprecationWarning)
            result = runner.run(suite)
        cases = result.cases + _deprecated_api_use(caught, module_name)
    except Exception:  # a broken test module is one error, not a silent pass
        cases = [{"name": module_name, "status": "error", "seconds": 0.0, "message": traceback.format_exc()}]
        print(cases[0]["message"])
    summary = write_results(cases, time.perf_counter() - start)
    failed = summary["failures"] + summary["errors"]
    sys.stdout.flush()
    sys.exit(1 if failed else 0)
