"""Conduction vs radiation in the heat the thermal silo's wall takes from the hot bed.

Runs demos/thermal_silo_radiation.toml (clinker at 800 K in a steel bin; particle-particle
and particle-wall radiation, seed 000 eqs. 22-23, beside the contact conduction) through
the one runner, ``--quick`` by default (60 s of heating with the heat-capacity scale
200), and the same case with ``dem.radiation = false`` (everything else equal, the outer
FE surface still radiating) for reference. From the coupling's energy books
(``bin_energy.csv``: Q_particles, the heat leaving the particles into the wall per
coupling step, and its radiated part Q_radiation) it reports the share of each, and
plots the heat flows into the wall and the running radiative share against the
physical heating time.

Energies are physical (the run's stored energies times the heat-capacity scale); heat
flows (W) and temperatures are physical in the scaled run as they are.

Usage: ``python benchmarks/silo_radiation_share.py [--full] [--out DIR] [--no-reference]``.
Writes ``DIR/silo_radiation_share.png`` (default DIR ``out/silo_radiation_share``). Last
line: ``radiative_share=... conduction_share=... Q_wall_kJ=... Q_wall_no_bed_radiation_kJ=...``.
"""
import argparse
import copy
import pathlib
import time
import tomllib

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
CASE = ROOT / "demos" / "thermal_silo_radiation.toml"


def run(table, out, *, quick):
    """Run a case table; returns (energy records of the bin, heat-capacity scale, wall s)."""
    from gsi.case import case_from_table
    from gsi.run import run_case
    t0 = time.perf_counter()
    run_case(case_from_table(table, base_dir=CASE.parent), out=out, quick=quick,
             verbose=False, pictures=False, overwrite=True)
    h = np.genfromtxt(out / "bin_energy.csv", delimiter=",", names=True)
    return h, table["run"]["heat_time_scale"], time.perf_counter() - t0


def without_bed_radiation(table):
    """The same case with the particle radiation off (the FE surface radiation kept)."""
    t = copy.deepcopy(table)
    for key in ("radiation", "radiation_cutoff", "radiation_every"):
        t["dem"].pop(key, None)
    t["case"]["name"] = "thermal_silo_no_bed_radiation"
    return t


def plot(h, ref, s, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    dt = h["t"][0]
    t = h["t_thermal"]
    rad = h["Q_radiation"] / dt
    cond = (h["Q_particles"] - h["Q_radiation"]) / dt
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    a.plot(t, cond, label="conduction (contacts)")
    a.plot(t, rad, label="radiation (bed within the cut-off)")
    a.plot(t, cond + rad, "k", lw=1.2, label="total")
    if ref is not None:
        a.plot(ref["t_thermal"], ref["Q_particles"] / dt, "k--", lw=1,
               label="total, no bed radiation")
    a.set_xlabel("heating time (s)")
    a.set_ylabel("heat flow from the bed into the wall (W)")
    a.legend(fontsize=8)
    Q_cum = np.cumsum(h["Q_particles"])
    ok = Q_cum > 0
    b.plot(t[ok], 100 * np.cumsum(h["Q_radiation"])[ok] / Q_cum[ok], "C1")
    b.set_xlabel("heating time (s)")
    b.set_ylabel("radiated share of the wall's heat so far (%)")
    b.set_ylim(0, 100)
    fig.suptitle("Thermal silo: clinker at 800 K, steel bin (eps 0.9 / 0.8), "
                 f"heat-capacity scale {s:g}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="the full case instead of --quick")
    ap.add_argument("--out", default="out/silo_radiation_share", help="output directory")
    ap.add_argument("--no-reference", action="store_true",
                    help="skip the run without particle radiation")
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    table = tomllib.loads(CASE.read_text())
    quick = not args.full
    h, s, wall = run(table, out / "radiation", quick=quick)
    ref = None
    if not args.no_reference:
        ref, _, wall_ref = run(without_bed_radiation(table), out / "reference", quick=quick)
    Q = h["Q_particles"].sum()
    Q_rad = h["Q_radiation"].sum()
    share = Q_rad / Q
    plot(h, ref, s, out / "silo_radiation_share.png")
    kJ = s / 1e3
    print(f"thermal_silo_radiation {'full' if args.full else 'quick'}: "
          f"{h['t_thermal'][-1]:g} s of heating, {len(h)} coupling steps, run {wall:.0f} s; "
          f"heat from the bed into the wall {Q * kJ:.4g} kJ: conduction "
          f"{(Q - Q_rad) * kJ:.4g} kJ, radiation {Q_rad * kJ:.4g} kJ ({100 * share:.1f} %); "
          f"last step {h['Q_particles'][-1] / h['t'][0]:.4g} W of which radiation "
          f"{h['Q_radiation'][-1] / h['t'][0]:.4g} W; wall mean {h['T_wall_mean'][-1]:.2f} K, "
          f"max {h['T_wall_max'][-1]:.2f} K; max |drift| "
          f"{np.abs(h['drift']).max() * kJ * 1e3:.2g} J")
    if ref is not None:
        print(f"without bed radiation (run {wall_ref:.0f} s): bed -> wall "
              f"{ref['Q_particles'].sum() * kJ:.4g} kJ, wall mean {ref['T_wall_mean'][-1]:.2f} K")
    print(f"plot: {out / 'silo_radiation_share.png'}")
    print(f"radiative_share={share:.4f} conduction_share={1 - share:.4f} "
          f"Q_wall_kJ={Q * kJ:.5g} Q_wall_no_bed_radiation_kJ="
          f"{ref['Q_particles'].sum() * kJ if ref is not None else float('nan'):.5g}")


if __name__ == "__main__":
    main()
