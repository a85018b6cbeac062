#!/usr/bin/env bash
# Configures and builds the sanitizer build into ./build-sanitize (or $ORACLEMESH_SANITIZE_DIR):
# the core library (no VTK), its GoogleTest suite and the fuzz harnesses, with clang, AddressSanitizer
# and UndefinedBehaviorSanitizer (every report stops the program), and the libFuzzer executables.
# Needs the packages of scripts/setup-debian.sh (clang, libclang-rt-14-dev). Uses ninja and ccache
# when present. Run its tests with `ctest` in that folder (scripts/test.sh does).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${ORACLEMESH_SANITIZE_DIR:-$root/build-sanitize}"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
if [ ! -f "$build/CMakeCache.txt" ]; then
  # -O1 with line tables: symbolized reports, and the Mesh_3 translation unit compiles in about
  # the time of the release build's
  cmake -S "$root" -B "$build" "${generator[@]}" "${launcher[@]}" \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DORACLEMESH_CORE_ONLY=ON -DORACLEMESH_SANITIZERS=address,undefined \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" "$@"
fi
cmake --build "$build" --parallel "$(nproc)"
