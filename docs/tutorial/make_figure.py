"""The tutorial's picture and Janssen table from a run of silo_study.py:

    python docs/tutorial/silo_study.py --quick --out out/silo2 > out/silo2.log
    python docs/tutorial/make_figure.py out/silo2 out/silo2.log

writes docs/_static/tutorial_silo.png (a snapshot beside three monitors) and
docs/_static/tutorial_silo_janssen.txt (the comparison lines of the log)."""
import csv
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STATIC = pathlib.Path(__file__).resolve().parents[1] / "_static"


def column(path, name):
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    return [float(r["time_s"]) for r in rows], [float(r[name]) for r in rows]


def main(run, log, frame="frame_0007.png"):
    run = pathlib.Path(run)
    img = plt.imread(run / "pictures" / frame)
    img = img[int(0.05 * img.shape[0]):]
    fig = plt.figure(figsize=(10, 4.6), dpi=90)
    ax = fig.add_axes([0.0, 0.0, 0.5, 1.0])
    ax.imshow(img)
    ax.axis("off")
    series = [("bed.csv", "count", 1.0, "beads in the domain"),
              ("hopper.csv", "Fz_N", -1.0, "hopper cone: vertical load (N)"),
              ("silo.csv", "load_z_N", -1.0, "silo wall: vertical load (N)")]
    for k, (f, col, scale, label) in enumerate(series):
        a = fig.add_axes([0.6, 0.72 - 0.29 * k, 0.38, 0.21])
        t, v = column(run / "monitors" / f, col)
        a.plot(t, [scale * x for x in v], lw=1.6)
        a.axvline(0.6, color="grey", lw=0.8, ls="--")
        a.set_title(label, fontsize=9, loc="left")
        a.tick_params(labelsize=8)
        a.grid(alpha=0.3)
        if k < 2:
            a.set_xticklabels([])
    a.set_xlabel("time (s)   (dashed: the gate starts to open)", fontsize=9)
    fig.savefig(STATIC / "tutorial_silo.png", dpi=90)
    lines = [l for l in pathlib.Path(log).read_text().splitlines()
             if l.startswith(("t = ", "wall load", "  Janssen"))]
    (STATIC / "tutorial_silo_janssen.txt").write_text("\n".join(lines) + "\n")
    print(STATIC / "tutorial_silo.png")


if __name__ == "__main__":
    main(*sys.argv[1:])
