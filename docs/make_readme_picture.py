"""Make docs/_static/hopper_membrane.png (the README's and the landing page's picture)
from a run of the hopper demo: a snapshot beside three of its monitors.

    gsi run demos/hopper_membrane.toml --quick --out out/hm
    python docs/make_readme_picture.py out/hm [FRAME]       # FRAME: pictures/frame_NNNN.png
"""
import csv
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def column(path, name):
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    return [float(r["time_s"]) for r in rows], [float(r[name]) for r in rows]


def main(run, frame=None):
    run = pathlib.Path(run)
    frame = pathlib.Path(frame) if frame else sorted((run / "pictures").glob("frame_*.png"))[-1]
    img = plt.imread(frame)
    h, w = img.shape[:2]
    img = img[int(0.05 * h):h]        # drop the title strip
    fig = plt.figure(figsize=(10, 4.2), dpi=90)
    ax = fig.add_axes([0.0, 0.0, 0.56, 1.0])
    ax.imshow(img)
    ax.axis("off")
    series = [("discharged.csv", "mass_kg", 1.0, "discharged (kg)"),
              ("membrane.csv", "max_displacement_m", 1e3, "membrane: max deflection (mm)"),
              ("membrane.csv", "load_z_N", -1.0, "membrane: load (N)")]
    for k, (f, col, scale, label) in enumerate(series):
        a = fig.add_axes([0.64, 0.71 - 0.29 * k, 0.34, 0.22])
        t, v = column(run / "monitors" / f, col)
        a.plot(t, [scale * x for x in v], lw=1.6, color="tab:blue")
        a.set_title(label, fontsize=9, loc="left")
        a.tick_params(labelsize=8)
        a.grid(alpha=0.3)
        if k < 2:
            a.set_xticklabels([])
    a.set_xlabel("time (s)", fontsize=9)
    out = pathlib.Path(__file__).resolve().parent / "_static" / "hopper_membrane.png"
    fig.savefig(out, dpi=90)
    print(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
