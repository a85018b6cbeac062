#!/usr/bin/env bash
# The test command, from a fresh Debian 12 machine: install, build, run every test (GoogleTest,
# Python, pvpython) through ctest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup-debian.sh"
bash "$root/scripts/build.sh"
build="${ORACLEMESH_BUILD_DIR:-$root/build}"
cd "$build"
ctest --output-on-failure --parallel "$(nproc)" --timeout 900
