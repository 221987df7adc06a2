#!/usr/bin/env bash
# Builds the core for systems older than Debian 12 and packs it with what it needs:
# dist/bakegi-<version>-linux-x64-portable.zip (issue 13, item 3; not yet run by CI).
#
# The build runs in a Debian 11 root made with debootstrap (glibc 2.31, GCC 10, Embree 3.12,
# TBB 2020, OpenEXR 2.5), links the C++ runtime statically, copies the Embree, TBB and
# OpenEXR libraries it needs next to libbakegi.so with the run path $ORIGIN, and checks
# that nothing asks for glibc above 2.31. Then `tools/check_portable.sh` loads that zip's
# library in a clean root and bakes the Cornell box.
#   BAKEGI_PORTABLE_ROOT  the build root (default ~/.cache/bakegi/bullseye-build; made once,
#                         about 1.5 minutes and 400 MB, reused while it has the packages)
# As root (debootstrap and chroot).
set -euo pipefail
cd "$(dirname "$0")/.."
root=${BAKEGI_PORTABLE_ROOT:-$HOME/.cache/bakegi/bullseye-build}
mirror=${BAKEGI_DEBIAN_MIRROR:-http://deb.debian.org/debian}
packages=build-essential,cmake,ninja-build,pkg-config,patchelf,zlib1g-dev,libembree-dev,libtbb-dev,libopenexr-dev,libglm-dev,libeigen3-dev,libboost-dev,libmeshoptimizer-dev,libstb-dev
max_glibc=2.31

command -v debootstrap >/dev/null || { apt-get update -qq && apt-get install -y -qq debootstrap >/dev/null; }
if [ ! -x "$root/usr/bin/patchelf" ] || [ ! -d "$root/usr/include/embree3" ] \
   || [ ! -f "$root/usr/include/meshoptimizer.h" ] || [ ! -d "$root/usr/include/stb" ]; then
  echo "== making the Debian 11 build root $root"
  rm -rf "$root"
  debootstrap --variant=minbase --include="$packages" bullseye "$root" "$mirror" >/dev/null
fi

echo "== building the core in it"
rm -rf "$root/src"
mkdir -p "$root/src"
cp -r CMakeLists.txt native "$root/src/"
chroot "$root" bash -c "cd /src && cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DBAKEGI_BUILD_TESTS=OFF -DBAKEGI_BUILD_BENCH=OFF \
  '-DCMAKE_SHARED_LINKER_FLAGS=-static-libstdc++ -static-libgcc' \
  '-DCMAKE_EXE_LINKER_FLAGS=-static-libstdc++ -static-libgcc' >/dev/null && \
  cmake --build build -j2 --target bakegi_shared bakegi_cli"

echo "== bundling its libraries"
out=build-portable
rm -rf "$out"
mkdir -p "$out/lib"
cp "$root/src/build/libbakegi.so" "$root/src/build/bakegi" "$out/"
# Every library it loads that is not glibc's own (or zlib, on every system) goes beside it.
chroot "$root" ldd /src/build/libbakegi.so | awk '/=>/ {print $3}' | while read -r path; do
  case "$(basename "$path")" in
    libc.so*|libm.so*|libpthread.so*|libdl.so*|librt.so*|libgcc_s.so*|libz.so*|ld-linux*) ;;
    libstdc++.so*) ;;  # the bundled libraries use the system's (GLIBCXX 3.4.26 at most)
    *) cp -L "$root$path" "$out/lib/" ;;
  esac
done
cp "$out/libbakegi.so" "$out/lib/"
rm "$out/libbakegi.so"
for library in "$out"/lib/*.so*; do
  # patchelf from the build root, on a copy (the host need not have it)
  cp "$library" "$root/tmp/patch.so"
  chroot "$root" patchelf --set-rpath '$ORIGIN' /tmp/patch.so
  cp "$root/tmp/patch.so" "$library"
done

echo "== checking symbol versions (glibc <= $max_glibc)"
newest=$(for library in "$out"/lib/*.so*; do objdump -T "$library" | grep -o 'GLIBC_[0-9.]*'; done \
  | sed 's/GLIBC_//' | sort -uV | tail -n 1)
echo "newest glibc symbol version: $newest; C++ runtime: $(for library in "$out"/lib/*.so*; do \
  objdump -T "$library" | grep -o 'GLIBCXX_[0-9.]*'; done | sort -uV | tail -n 1)"
if [ "$(printf '%s\n%s\n' "$newest" "$max_glibc" | sort -V | tail -n 1)" != "$max_glibc" ]; then
  echo "build_portable: a library needs glibc $newest (more than $max_glibc)" >&2
  exit 1
fi
ls -l "$out/lib"

echo "== packing"
/usr/bin/python3 tools/make_addon_zip.py --build-dir "$out/lib" --bundle "$out/lib" --out dist --suffix portable
