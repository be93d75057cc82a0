#!/usr/bin/env bash
# install.sh - the installed library as a user meets it: `cmake --install` into a temporary
# prefix, then the README's embedding example (the ```c block of "Using the library") built
# against the installed copy only, with `pkg-config --cflags --libs radiosity` (shared library)
# and with find_package(radiosity) (shared and static targets), and run on scenes/room.obj.
# Usage: install.sh RADIOSITY SOURCE_DIR BUILD_DIR C_COMPILER [EXTRA_CFLAGS]
# EXTRA_CFLAGS: the sanitizer build passes -fsanitize=address,undefined, since a library built
# with the sanitizers can only be loaded by a program that carries their runtime.
source "$(dirname "$0")/lib_cli.sh" "$@"
build=$(realpath "$3")
cc=$4
extra=${5:-}

prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" >"$work/install.log" 2>&1
check "cmake --install" test $? -eq 0
check "header installed" test -f "$prefix/include/radiosity.h"
check "tool installed" test -x "$prefix/bin/radiosity"
libdir=$(dirname "$(find "$prefix" -name libradiosity.a | head -1)")
check "static library installed" test -f "$libdir/libradiosity.a"
check "shared library installed" test -f "$libdir/libradiosity.so"
check "pkg-config file installed" test -f "$libdir/pkgconfig/radiosity.pc"
check "cmake package installed" test -f "$libdir/cmake/radiosity/radiosityConfig.cmake"
"$prefix/bin/radiosity" --version >/dev/null 2>&1 || "$prefix/bin/radiosity" scenes >/dev/null
check "installed tool runs" test $? -eq 0

# The README's example, exactly as printed there.
awk '/^## Using the library/ {inside = 1} inside && /^```c$/ {code = 1; next}
     code && /^```$/ {exit} code {print}' "$source_dir/README.md" >"$work/room.c"
check "README has the example" grep -q 'int main' "$work/room.c"
scene=$source_dir/scenes/room.obj

# pkg-config: nothing from the build tree, only the installed prefix.
export PKG_CONFIG_PATH=$libdir/pkgconfig
flags=$(pkg-config --cflags --libs radiosity)
check "pkg-config knows radiosity" test $? -eq 0
check "pkg-config points into the prefix" \
    test "$(realpath "$(pkg-config --variable=libdir radiosity)")" = "$(realpath "$libdir")"
# shellcheck disable=SC2086
$cc -std=c11 $extra "$work/room.c" $flags -o "$work/room_pc" 2>"$work/cc.log"
check "example builds with pkg-config" test $? -eq 0 || cat "$work/cc.log" >&2
LD_LIBRARY_PATH=$libdir "$work/room_pc" "$scene" >"$work/out_pc" 2>"$work/err_pc"
check "example runs (pkg-config, shared)" test $? -eq 0
check "example solved the room" grep -Eq '^[0-9]+ elements, [0-9]+ shots' "$work/out_pc"
check "example linked the installed shared library" \
    grep -q "=> $libdir/libradiosity.so" <<<"$(LD_LIBRARY_PATH=$libdir ldd "$work/room_pc")"
LD_LIBRARY_PATH=$libdir "$work/room_pc" "$work/missing.obj" >/dev/null 2>"$work/err_missing"
check "example reports a missing scene" test $? -eq 1
check "one line for it" test "$(wc -l <"$work/err_missing")" -eq 1

# find_package(radiosity): the shared target and the static one.
mkdir -p "$work/cmake_app"
cp "$work/room.c" "$work/cmake_app/"
cat >"$work/cmake_app/CMakeLists.txt" <<EOF
cmake_minimum_required(VERSION 3.18)
project(room C)
find_package(radiosity REQUIRED)
add_executable(room_shared room.c)
target_link_libraries(room_shared radiosity::radiosity)
if(NOT TARGET radiosity::radiosity_static)
  message(FATAL_ERROR "radiosity::radiosity_static is missing")
endif()
add_executable(room_static room.c)
target_link_libraries(room_static radiosity::radiosity_static)
EOF
cmake -S "$work/cmake_app" -B "$work/cmake_build" -DCMAKE_PREFIX_PATH="$prefix" \
      -DCMAKE_C_COMPILER="$cc" -DCMAKE_C_FLAGS="$extra" -DCMAKE_EXE_LINKER_FLAGS="$extra" \
      >"$work/cmake.log" 2>&1
check "find_package(radiosity) configures" test $? -eq 0 || cat "$work/cmake.log" >&2
cmake --build "$work/cmake_build" -j 2 >"$work/build.log" 2>&1
check "find_package example builds" test $? -eq 0 || tail -20 "$work/build.log" >&2
"$work/cmake_build/room_shared" "$scene" >"$work/out_shared" 2>&1
check "example runs (find_package, shared)" test $? -eq 0
"$work/cmake_build/room_static" "$scene" >"$work/out_static" 2>&1
check "example runs (find_package, static)" test $? -eq 0
check "the same answer from all three" cmp -s "$work/out_pc" "$work/out_shared"
check "static agrees" cmp -s "$work/out_pc" "$work/out_static"

finish
