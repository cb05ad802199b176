#!/usr/bin/env bash
# Installs sb3-pnn with its development extras into the current Python.
# torch: an installed torch (any build, >=2.3) is kept. Without one, torch==2.13.0 is asked for,
# which on our CI machines resolves to a CPU build held on local disk; elsewhere pip picks the
# default build for your platform. Set SB3_PNN_TORCH to ask for another spec.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
if ! "$PY" -c "import torch" >/dev/null 2>&1; then
  "$PY" -m pip install --quiet "${SB3_PNN_TORCH:-torch==2.13.0}"
fi
"$PY" -m pip install --quiet -e ".[dev]"
