"""A bed of particles at rest on a clamped membrane (docs/design.md, "Validation cases",
case 8).

A single layer of n x n softwood spheres (seed 000, Table 3; plus rolling resistance so
that they come to rest) is placed just above the top face of a clamped circular plate
and coupled to it (the structure set up by :meth:`gsi.case.structure.Structure.build`,
its wall material derived from the plate's; :class:`gsi.coupling.staggered.StaggeredCoupling`);
the plate is dynamic with mass-proportional damping (damping ratio ``zeta`` of its lowest mode) or
quasi-static with under-relaxation. At rest:

* the support reactions carry the bed's weight (the membrane's self-weight is off);
* the deflection equals a static FE solve under the same nodal loads;
* at every coupling step the nodal loads sum to minus the time-averaged wall force on
  the particles, to round-off.

Used by tests/validation/test_coupling_bed_on_membrane.py and the MPI test; runnable on
its own: ``python -m gsi.studies.bed_on_membrane`` prints the key numbers.
"""
from __future__ import annotations


import numpy as np
from mpi4py import MPI

#: softwood (XDEM Table 3) with rolling resistance; the membrane (a stiffer rubber)
SOFTWOOD = dict(E=5.0e5, nu=0.45, rho=400.0, e=0.5, mu=0.8, mu_r=0.1)
PLATE = dict(E=2.0e7, nu=0.45, rho=930.0)


def bed_on_membrane(*, h: float = 0.05, degree: int = 2, scheme: str = "generalized_alpha",
                    rho_inf: float = 0.8, zeta: float = 0.5, relaxation: float = 1.0, n: int = 6,
                    radius: float = 0.2, thickness: float = 0.01, r: float = 0.01,
                    n_thickness: int = 1, duration: float = 0.5, n_sub: int | None = None,
                    comm=MPI.COMM_WORLD):
    """Run the bed case; returns a dict of key numbers (same on every rank).

    Parameters
    ----------
    h : float
        Membrane element size (m).
    degree : int
        FE degree (1 or 2).
    scheme : {"generalized_alpha", "newmark", "static"}
        FE integrator (static: quasi-static coupling).
    rho_inf : float
        Spectral radius at infinity of generalized-alpha (damps the high modes that the
        sub-cycle-averaged loads excite).
    zeta : float
        Damping ratio of the lowest mode (a0 = 2 zeta omega_1), dynamic schemes.
    relaxation : float
        Quasi-static under-relaxation.
    n : int
        Spheres per side of the square layer.
    radius, thickness : float
        Membrane radius and thickness (m).
    r : float
        Sphere radius (m).
    duration : float
        Simulated time (s).
    n_sub : int, optional
        DEM steps per FE step (default: :func:`choose_n_sub`).

    Returns
    -------
    dict
        ``weight`` (N), ``reaction`` (3,) (N, supports on the membrane), ``load`` (3,)
        (N, last step), ``records`` (the coupling history dict), ``u_max`` (m, interface
        max |u|), ``u_static_max`` (m, static solve under the last loads),
        ``u_diff_rel`` (-, max |u - u_static| / max |u_static| at the interface nodes),
        ``kinetic_energy`` (J, particles at the end), ``T_1`` (s), ``n_sub``, ``n_dofs``.
    """
    from gsi.case.structure import Contact, Structure
    from gsi.coupling.interface import SurfaceInterface
    from gsi.dem import Material, Simulation
    from gsi.dem.materials import rayleigh_time
    from gsi.fem.elasticity import Elasticity

    root = 0
    spec = Structure(
        name="membrane", mesh="membrane",
        geometry=dict(shape="circle", radius=radius, thickness=thickness, h=h,
                      n_thickness=n_thickness),
        material="rubber", **PLATE, degree=degree, scheme=scheme, rho_inf=rho_inf,
        damping_ratio=zeta, supports=["support"],
        contact=Contact(tags=("contact",), e=0.5, mu=0.8, mu_r=0.1, n_sub=n_sub,
                        relaxation=relaxation))
    wood = Material(**SOFTWOOD)
    dt = 0.2 * rayleigh_time(r, wood)
    cs = spec.build(comm=comm, dt_dem=dt, gravity=(0.0, 0.0, -9.81), root=root)
    el, T_1, n_sub = cs.elasticity, cs.T_1, cs.n_sub
    sim = None
    if comm.rank == root:
        wall_name, wall_mat = spec.dem_wall_material({"wood": wood})
        sim = Simulation({"wood": wood, wall_name: wall_mat},
                         rolling=True, dt=dt, skin=0.4 * r,
                         domain=((-1.5 * radius,) * 2 + (-radius,), (1.5 * radius,) * 2 + (radius,)))
        s = 2.05 * r
        g = (np.arange(n) - 0.5 * (n - 1)) * s
        X, Y = np.meshgrid(g, g)
        x = np.c_[X.ravel(), Y.ravel(), np.full(X.size, thickness + 1.02 * r)]
        sim.add_particles(x, r, material="wood")
    cs.attach(sim)
    cp = cs.mechanics
    cp.run(int(round(duration / cp.dt)))
    info = None
    if comm.rank == root:
        info = (float(sim.mass.sum() * 9.81), sim.kinetic_energy())
    weight, ke = comm.bcast(info, root=root)
    reaction = el.reaction("support")
    u = cp.interface.displacement()
    # a static solve under the same nodal loads
    check = Elasticity(cs.mesh, cs.material, degree=degree)
    check.clamp("support")
    itf_check = SurfaceInterface(check)
    itf_check.add_nodal_loads(cp.last_loads, root=None)
    check.solve()
    u_s = itf_check.displacement()
    umag = np.sqrt((u ** 2).sum(axis=1))
    us_mag = np.sqrt((u_s ** 2).sum(axis=1))
    return dict(weight=weight, reaction=reaction, load=cp.held_load(), records=cp.history(),
                u_max=float(umag.max()), u_static_max=float(us_mag.max()),
                u_diff_rel=float(np.abs(u - u_s).max() / us_mag.max()), kinetic_energy=ke,
                T_1=T_1, n_sub=n_sub, n_dofs=el.n_dofs, dt_fe=cp.dt)


if __name__ == "__main__":
    res = bed_on_membrane()
    if MPI.COMM_WORLD.rank == 0:
        print({k: v for k, v in res.items() if k != "records"})
