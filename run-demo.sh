#!/usr/bin/env bash
# Set up (a virtual environment in .venv with the project installed) and run the
# rig on the bundled laboratory pair: NSTAR and ESTAR as two processes over
# ./jhdata, the 1985 position tables on screen, pictures in ./out.
# Installs only when .venv is missing or pyproject.toml has changed since.
set -euo pipefail
cd "$(dirname "$0")"
stamp=.venv/.installed-from
want="$(cksum < pyproject.toml)"
if [ ! -x .venv/bin/python ]; then
    echo "== making a virtual environment in .venv (once)"
    python3 -m venv .venv
fi
if [ ! -x .venv/bin/rig ] || [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
    echo "== installing the project into .venv (numpy, opencv, numba...; once, or after"
    echo "   pyproject.toml changes; takes a minute the first time)"
    .venv/bin/python -m pip install -qq --disable-pip-version-check -e '.[test]'
    echo "$want" > "$stamp"
else
    echo "== .venv is up to date (delete $stamp to reinstall)"
fi
if ! ls nstar/__pycache__/*.nbi >/dev/null 2>&1; then
    echo "== first run: numba compiles the rig's kernels (10-20 s; cached for later runs)"
fi
status=0
.venv/bin/rig demo "$@" || status=$?
cat <<'TIP'

== In a new terminal the commands (nstar, estar, rig, pre) are in .venv/bin:
   source .venv/bin/activate        # then: nstar, estar, rig scan, pre ...
   # or call them by path:  .venv/bin/nstar   .venv/bin/estar --help
TIP
exit "$status"
