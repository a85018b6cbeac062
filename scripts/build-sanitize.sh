#!/usr/bin/env bash
# Configures and builds the sanitizer build into ./build-sanitize (or $ORACLEMESH_SANITIZE_DIR):
# the core library (no VTK), its GoogleTest suite and the fuzz harnesses, with clang, AddressSanitizer
# and UndefinedBehaviorSanitizer (every report stops the program).
# Needs the packages of scripts/setup-debian.sh (clang, libclang-rt-14-dev). Uses ninja and ccache
# when present. Run its tests with `ctest` in that folder (scripts/test.sh does).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${ORACLEMESH_SANITIZE_DIR:-$root/build-sanitize}"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# Options after the script go to CMake (and configure again): -DORACLEMESH_FUZZ=ON adds libFuzzer's
# coverage instrumentation, the fuzz executables and the 'fuzz' target (slower tests: the CI's
# folder leaves it off; fuzz in a folder of its own, see docs/REFERENCE.md).
if [ ! -f "$build/CMakeCache.txt" ] || [ $# -gt 0 ]; then
  # -O1 with line tables: symbolized reports, and the Mesh_3 translation unit compiles in about
  # the time of the release build's
  cmake -S "$root" -B "$build" "${generator[@]}" "${launcher[@]}" \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DORACLEMESH_CORE_ONLY=ON -DORACLEMESH_SANITIZERS=address,undefined -DORACLEMESH_FUZZ=OFF \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" "$@"
fi
cmake --build "$build" --parallel "$(nproc)"
