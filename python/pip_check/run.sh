#!/usr/bin/env bash
# Installs frnn as a user would, with nothing downloaded, and checks the installed package:
#   /usr/bin/python3 -m venv --system-site-packages V
#   V/bin/pip install --no-build-isolation --no-deps .
#   V/bin/pip wheel --no-build-isolation --no-deps -w dist .
# pip builds in the source folder, so it runs on a copy of the sources in a temporary folder,
# which is removed on exit, also on failure.
set -euo pipefail
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
python=${FRNN_PIP_PYTHON:-/usr/bin/python3}
work=$(mktemp -d "${TMPDIR:-/tmp}/frnn-pip.XXXXXX")
trap 'rm -rf "$work"' EXIT

mkdir "$work/src"
tar -C "$source_dir" --exclude=./build --exclude='./build-*' --exclude=./.git \
    --exclude='*.egg-info' --exclude=__pycache__ -cf - . | tar -C "$work/src" -xf -

"$python" -m venv --system-site-packages "$work/venv"
# PIP_NO_INDEX: fail rather than download anything.
export PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1 PIP_NO_CACHE_DIR=1
start=$(date +%s)
"$work/venv/bin/pip" install -q --no-build-isolation --no-deps "$work/src"
echo "pip install: $(( $(date +%s) - start )) s"
start=$(date +%s)
"$work/venv/bin/pip" wheel -q --no-build-isolation --no-deps -w "$work/dist" "$work/src"
echo "pip wheel: $(( $(date +%s) - start )) s"

# Run from outside the sources, so that only the installed package can be imported.
cd "$work"
"$work/venv/bin/python" "$source_dir/python/pip_check/installed.py" "$work/venv" "$work/dist"
