#!/usr/bin/env bash
# Idempotent set-up for a fresh Debian 12 machine (run as root): Debian packages, a venv with
# the system's site packages, gsi installed editable, pyvista with numpy held at the system's
# version. A second run finds everything in place and returns in about a second.
set -euo pipefail
cd "$(dirname "$0")/.."

# the documentation (make docs, make docs-check): Sphinx, MyST, the furo theme (MathJax and
# normalize.css come with them) and a headless browser
DOCS_DEBS="python3-sphinx python3-myst-parser furo libjs-mathjax chromium"

# an optimized BLAS: Debian's default libblas.so.3 is netlib's reference BLAS, on which
# MUMPS's factorizations (direct solves, BDDC's set-up) run 4-8 times slower
# (docs/performance.md, "BDDC's set-up, and the BLAS"). The serial OpenBLAS becomes
# libblas.so.3/liblapack.so.3 by update-alternatives; serial, because gsi's parallelism is
# MPI ranks and numba threads, and a threaded BLAS under them would oversubscribe the cores.
BLAS_DEBS="libopenblas0-serial"

DEBS="python3-dolfinx python3-petsc4py python3-mpi4py python3-gmsh python3-meshio \
python3-numba python3-scipy python3-pytest liggghts python3-matplotlib python3-venv python3-pip \
openmpi-bin libgl1 libxrender1 libosmesa6 ${BLAS_DEBS} ${DOCS_DEBS} ${EXTRA_DEBS:-}"

missing=""
for p in $DEBS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  echo "setup: apt-get install$missing"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends $missing > /tmp/gsi-apt.log 2>&1 || { tail -20 /tmp/gsi-apt.log; exit 1; }
fi

if [ ! -x .venv/bin/python ]; then
  echo "setup: creating .venv (system site packages)"
  /usr/bin/python3 -m venv --system-site-packages .venv
fi

stamp=.venv/.gsi-installed
want=$(cat pyproject.toml .ci/setup.sh | sha1sum | cut -c1-16)
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$want" ]; then
  echo "setup: pip install -e .[viz] (numpy held at the system's version)"
  npv=$(/usr/bin/python3 -c 'import numpy; print(numpy.__version__)')
  echo "numpy==$npv" > .venv/constraints.txt
  .venv/bin/python -m pip install -q --disable-pip-version-check -c .venv/constraints.txt -e ".[viz]"
  echo "$want" > "$stamp"
fi
