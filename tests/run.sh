#!/usr/bin/env bash
# Builds everything and runs every test through one ctest run: the native build (warnings as
# errors), the clang ASan/UBSan + libFuzzer sub-build (parsers, fuzz corpora) and the aarch64
# cross build of the firmware (tests under qemu-aarch64, label "cross").
# Usage: tests/run.sh [extra ctest arguments, e.g. -L cross]
set -euo pipefail
cd "$(dirname "$0")/.."

build=${MOCAP_BUILD_DIR:-build}
jobs=$(nproc)
# ccache (when installed) keys on paths relative to the checkout, so every clone shares hits.
export CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1

# Test-side validators from PyPI live in a virtual environment of their own.
if [ -f tests/requirements.txt ]; then
    if [ ! -x .venv/bin/python ]; then
        python3 -m venv .venv
    fi
    .venv/bin/pip install --quiet --disable-pip-version-check -r tests/requirements.txt
fi

cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMOCAP_WERROR=ON -DMOCAP_SUBBUILDS=ON \
    -UMOCAP_HUB_LAYERS -UMOCAP_FIRMWARE_MODULES
cmake --build "$build" -j "$jobs"
# A test that hangs fails after 15 minutes instead of holding the whole run (tests that need
# longer set their own TIMEOUT property).
ctest --test-dir "$build" --output-on-failure --timeout 900 -j "$jobs" "$@"
