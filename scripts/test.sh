#!/usr/bin/env bash
# The test command, from a fresh Debian 12 machine: install, build, run every test (GoogleTest,
# Python, pvpython) through ctest; then the core's tests and the fuzz corpus again in the sanitizer
# build (clang, ASan + UBSan: any report fails the test).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup-debian.sh"
bash "$root/scripts/build.sh"
build="${ORACLEMESH_BUILD_DIR:-$root/build}"
cd "$build"
ctest --output-on-failure --parallel "$(nproc)" --timeout 900

bash "$root/scripts/build-sanitize.sh"
cd "${ORACLEMESH_SANITIZE_DIR:-$root/build-sanitize}"
ctest --output-on-failure --parallel "$(nproc)" --timeout 900
