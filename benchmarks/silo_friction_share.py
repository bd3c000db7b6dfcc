"""Friction beside conduction and radiation in the thermal silo wall's heat load.

Runs demos/thermal_silo_friction.toml (clinker at 800 K poured into a steel bin and left
to settle; contact conduction, particle radiation and frictional heating,
``dem.frictional_heating``) through the one runner, ``--quick`` by default. From the
coupling's energy record (``bin_energy.csv``: Q_particles, the heat leaving the particles
into the wall by conduction and radiation, its radiated part Q_radiation, and
Q_friction, the wall's half of the frictional heat of the particle-wall contacts) it
reports the share of each in the heat the wall takes, and the particles' energy book
(``monitors/energy.csv``: heat friction made in all contacts, drift).

Scaling: the case runs with ``heat_time_scale`` s (c_p and the wall's c divided by s),
so 1 s simulated stands for s seconds of heating; conduction and radiation energies are
physical once multiplied by s. The frictional heat is the dissipation of the simulated
mechanics: physical as it is for a one-off event such as this settling (the run's
temperatures overstate its effect s times), and multiplied by s if the flow were steady
(a discharge that lasts the whole heating time). Both shares are printed.

Usage: ``python benchmarks/silo_friction_share.py [--full] [--out DIR]``. Last line:
``friction_share=... friction_share_steady=... conduction_share=... radiative_share=...
Q_wall_kJ=... Q_friction_J=... heat_generated_J=... drift_rel=...``.
"""
import argparse
import pathlib
import time
import tomllib

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
CASE = ROOT / "demos" / "thermal_silo_friction.toml"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="the full case instead of --quick")
    ap.add_argument("--out", default="out/silo_friction_share", help="output directory")
    args = ap.parse_args()
    from gsi.case import case_from_table
    from gsi.run import run_case
    out = pathlib.Path(args.out)
    table = tomllib.loads(CASE.read_text())
    t0 = time.perf_counter()
    run_case(case_from_table(table, base_dir=CASE.parent), out=out, quick=not args.full,
             verbose=False, pictures=False, overwrite=True)
    wall = time.perf_counter() - t0
    h = np.genfromtxt(out / "bin_energy.csv", delimiter=",", names=True)
    e = np.genfromtxt(out / "monitors" / "energy.csv", delimiter=",", names=True)
    s = table["run"]["heat_time_scale"]
    Q_rad = h["Q_radiation"].sum() * s
    Q_cond = h["Q_particles"].sum() * s - Q_rad
    Q_fr = h["Q_friction"].sum()
    total = Q_cond + Q_rad + Q_fr
    steady = Q_cond + Q_rad + Q_fr * s
    print(f"thermal_silo_friction {'full' if args.full else 'quick'}: "
          f"{h['t_thermal'][-1]:g} s of heating ({h['t'][-1]:g} s simulated), run {wall:.0f} s;"
          f" heat into the wall: conduction {Q_cond / 1e3:.4g} kJ, radiation "
          f"{Q_rad / 1e3:.4g} kJ, friction {Q_fr:.4g} J (x {s:g} if steady: "
          f"{Q_fr * s:.4g} J); friction made in all contacts {e['heat_generated_J'][-1]:.4g} J;"
          f" energy book drift {e['drift_rel'][-1]:.2e} of the energy in play")
    print(f"friction_share={Q_fr / total:.3e} friction_share_steady={Q_fr * s / steady:.3e} "
          f"conduction_share={Q_cond / total:.4f} radiative_share={Q_rad / total:.4f} "
          f"Q_wall_kJ={total / 1e3:.5g} Q_friction_J={Q_fr:.4g} "
          f"heat_generated_J={e['heat_generated_J'][-1]:.4g} drift_rel={e['drift_rel'][-1]:.3e}")


if __name__ == "__main__":
    main()
