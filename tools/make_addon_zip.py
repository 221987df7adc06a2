#!/usr/bin/env python3
"""Builds the installable add-on zip: dist/bakegi-<version>-<platform>.zip.

    python3 tools/make_addon_zip.py --build-dir build [--out dist]
    python3 tools/make_addon_zip.py --build-dir D --bundle D --suffix portable   # build_portable.sh

The zip holds bakegi/ (the add-on's Python files, blender_manifest.toml) and
bakegi/lib/libbakegi.so copied from the build directory, so that installing it through
Blender's add-on preferences needs no other file. With --bundle, every other shared library
in that folder goes into bakegi/lib/ too (the libraries a portable build carries, found
through its $ORIGIN run path). Plain Python, no bpy.
"""

import argparse
import ast
import pathlib
import platform
import sys
import zipfile

REPO = pathlib.Path(__file__).resolve().parent.parent
ADDON = REPO / "addon" / "bakegi"
LIBRARY_NAME = "libbakegi.so"


def addon_version():
    """bl_info["version"] of addon/bakegi/__init__.py, read without importing it."""
    tree = ast.parse((ADDON / "__init__.py").read_text())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id == "bl_info" for t in node.targets):
            info = ast.literal_eval(node.value)
            return ".".join(str(v) for v in info["version"])
    raise SystemExit("bl_info not found in addon/bakegi/__init__.py")


def platform_tag():
    machine = {"x86_64": "x64", "amd64": "x64", "aarch64": "arm64"}.get(
        platform.machine().lower(), platform.machine().lower())
    return f"{sys.platform.rstrip('0123456789')}-{machine}"


def addon_files():
    for path in sorted(ADDON.rglob("*")):
        relative = path.relative_to(ADDON)
        if path.is_dir() or any(part.startswith(".") or part == "__pycache__"
                                for part in relative.parts):
            continue
        if path.suffix in (".pyc", ".so") or relative.parts[0] == "lib":
            continue
        yield path, relative


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build-dir", required=True, type=pathlib.Path,
                        help=f"CMake build directory holding {LIBRARY_NAME}")
    parser.add_argument("--out", default=REPO / "dist", type=pathlib.Path,
                        help="output directory (default: dist/)")
    parser.add_argument("--bundle", type=pathlib.Path,
                        help="a folder of shared libraries to carry beside the core library")
    parser.add_argument("--suffix", default="", help="added to the zip's name (e.g. portable)")
    args = parser.parse_args(argv)

    library = args.build_dir / LIBRARY_NAME
    if not library.is_file():
        raise SystemExit(f"{library} not found: build the 'bakegi' target first")
    args.out.mkdir(parents=True, exist_ok=True)
    suffix = f"-{args.suffix}" if args.suffix else ""
    zip_path = args.out / f"bakegi-{addon_version()}-{platform_tag()}{suffix}.zip"
    bundled = sorted(p for p in args.bundle.iterdir() if ".so" in p.name and p.name != LIBRARY_NAME
                     and p.is_file()) if args.bundle else []
    with zipfile.ZipFile(zip_path, "w", zipfile.ZIP_DEFLATED) as archive:
        for path, relative in addon_files():
            archive.write(path, (pathlib.Path("bakegi") / relative).as_posix())
        info = zipfile.ZipInfo.from_file(library.resolve(), f"bakegi/lib/{LIBRARY_NAME}")
        info.compress_type = zipfile.ZIP_DEFLATED
        with open(library.resolve(), "rb") as source:
            archive.writestr(info, source.read())
        for path in bundled:
            archive.write(path, f"bakegi/lib/{path.name}")
    print(zip_path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
