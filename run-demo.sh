#!/usr/bin/env bash
# Set up (a virtual environment in .venv with the project installed) and run the
# rig on the bundled laboratory pair: NSTAR and ESTAR as two processes over
# ./jhdata, the 1985 position tables on screen, pictures in ./out.
set -euo pipefail
cd "$(dirname "$0")"
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --upgrade pip
.venv/bin/python -m pip install --quiet -e '.[test]'
exec .venv/bin/rig demo "$@"
