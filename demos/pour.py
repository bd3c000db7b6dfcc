"""Pour: glass beads fall into a box and settle into a bed.

The smallest complete gsi case. 2,000 beads (radius 1.8–2.2 mm, soft glass as in the
LIGGGHTS settle benchmark, Hertz–Mindlin with tangential history) are placed at random in
a region above a 6 x 6 cm open box and fall under gravity. As the bed comes to rest, the
vertical force of the particles on the walls approaches their weight — the balance the
summary prints.

The case lives in ``pour.toml`` beside this script (``gsi run demos/pour.toml`` runs the
same case). Output: ``particles.pvd`` (open in ParaView), ``history.csv``, ``pour.png``
and ``history.png``.

Run: ``python demos/pour.py [--quick] [--out DIR]``
"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from _common import main  # noqa: E402

CASE = pathlib.Path(__file__).with_suffix(".toml")

if __name__ == "__main__":
    result = main(CASE, __doc__.splitlines()[0])
