#!/usr/bin/env bash
# Installs sb3-pnn with its development extras into the current Python.
# torch: an installed torch (any build, >=2.3) is kept. Without one, torch==2.13.0 is asked for,
# which on our CI machines resolves to a CPU build held on local disk; elsewhere pip picks the
# default build for your platform. Set SB3_PNN_TORCH to ask for another spec.
# Prints one line per step (pip itself runs quietly; the steps take a minute or more).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
step() { printf 'setup.sh: %s\n' "$*"; }
started=$SECONDS
if torch_version=$("$PY" -c "import torch; print(torch.__version__)" 2>/dev/null); then
  step "keeping the installed torch $torch_version"
else
  spec=${SB3_PNN_TORCH:-torch==2.13.0}
  step "no torch found: installing $spec (a large download) ..."
  "$PY" -m pip install --quiet "$spec"
fi
step "installing sb3-pnn (editable) with its dev extras (rl_zoo3, optuna, pytest, ...): a minute or so ..."
"$PY" -m pip install --quiet -e ".[dev]"
step "done in $((SECONDS - started)) s; next: python3 -m sb3_pnn.reproduce --quick or bash scripts/test.sh"
