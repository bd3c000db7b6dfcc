"""Checks of a case that a careful but hurried user needs (issue "bad input a careful user
actually types"): output names that are not paths, a ``[[pairs]]`` entry given twice,
geometric contradictions (a fill region through a wall plane, a lattice fill crossing a
cone, a wall plane, structure or monitor region outside the domain) and the explicit
heat update's stability bound, computable before the run."""
from __future__ import annotations

import math

import numpy as np

from gsi.case.names import check_name, check_unique_across
from gsi.case.structure_checks import check_structures
from gsi.meshes.footprint import point_triangle_distance
from gsi.errors import GsiInputError

__all__ = ["check_output_names", "check_pairs", "check_planes_and_fills",
           "check_monitor_regions", "check_heat_stability", "check_lattices_against_walls",
           "check_friction_stability", "check_geometry", "check_stability", "check_lengths",
           "MU_CAPPED"]


def check_output_names(case) -> None:
    """Every name that becomes a file or a monitor target follows :mod:`gsi.case.names`;
    walls and structures share one name space (a wall monitor's target names either)."""
    for section, what in (("particles", "a group name"), ("walls", "walls/<name>.vtu"),
                          ("structures", "<name>.xdmf"), ("monitors", "monitors/<name>.csv")):
        for i, item in enumerate(getattr(case, section)):
            check_name(f"{section}[{i}].name", item.name, what)
    check_unique_across([(f"walls[{i}].name", w.name) for i, w in enumerate(case.walls)]
                        + [(f"structures[{i}].name", s.name)
                           for i, s in enumerate(case.structures)], "wall and structure")
    check_pairs(case)


def check_pairs(case) -> None:
    """A material pair given twice (in either order) would let one entry win silently."""
    seen: dict[frozenset, int] = {}
    for i, p in enumerate(case.pairs):
        key = frozenset(p.materials)
        if key in seen:
            raise GsiInputError(f"pairs[{i}].materials = {list(p.materials)}: the same pair as "
                                f"pairs[{seen[key]}] (order does not matter); give each pair once")
        seen[key] = i


def _region_box(region) -> tuple[np.ndarray, np.ndarray]:
    """Axis-aligned bounding box of a region (box, sphere, cylinder)."""
    if region.kind == "box":
        return np.asarray(region.lo, float), np.asarray(region.hi, float)
    c = np.asarray(region.centre, float)
    r = float(region.radius)
    if region.kind == "sphere":
        return c - r, c + r
    ax = _axis(region)
    mid = c + 0.5 * float(region.length) * ax
    half = 0.5 * float(region.length) * np.abs(ax) + r * np.sqrt(np.clip(1.0 - ax ** 2, 0, 1))
    return mid - half, mid + half


def _axis(region) -> np.ndarray:
    ax = np.asarray(region.axis if region.axis is not None else (0.0, 0.0, 1.0), float)
    return ax / np.linalg.norm(ax)


def _middle(region) -> np.ndarray:
    """Centre of a sphere; middle of a cylinder (its ``centre`` is one end's axis point)."""
    c = np.asarray(region.centre, float)
    return c if region.kind == "sphere" else c + 0.5 * float(region.length) * _axis(region)


def _corners(lo, hi) -> np.ndarray:
    return np.array([[a, b, c] for a in (lo[0], hi[0]) for b in (lo[1], hi[1])
                     for c in (lo[2], hi[2])])


def check_planes_and_fills(case) -> None:
    """A plane wall wholly outside the domain box (particles are lost before they reach
    it), and a fill region reaching through a plane (the particles behind it would be
    pushed through or lost): one-line errors naming the key."""
    dlo, dhi = np.asarray(case.dem.domain_lo, float), np.asarray(case.dem.domain_hi, float)
    size = float(np.max(dhi - dlo))
    for j, w in enumerate(case.walls):
        if w.kind != "plane":
            continue
        n = np.asarray(w.normal, float)
        n = n / np.linalg.norm(n)
        s = (_corners(dlo, dhi) - np.asarray(w.point, float)) @ n
        if (s > 1e-9 * size).all():
            raise GsiInputError(
                f"walls[{j}].point = {list(w.point)}: the plane lies outside dem.domain "
                f"({dlo.tolist()} to {dhi.tolist()}), {float(s.min()):.3g} m from it; particles "
                f"leave the domain before they reach it: move it into the domain (m)")
        for i, p in enumerate(case.particles):
            if p.region is None or p.fill == "file":
                continue
            lo, hi = _region_box(p.region)
            r = case.source_largest_radius(i) if p.size is not None else 0.0
            behind = float(((_corners(lo, hi) - np.asarray(w.point, float)) @ n).min())
            if p.region.kind != "box":     # the round regions: their own extent along n
                c = _middle(p.region)
                behind = float((c - np.asarray(w.point, float)) @ n) - _extent(p.region, n)
            if behind < -r - 1e-9 * size:
                raise GsiInputError(
                    f"particles[{i}].region: reaches {-behind:.3g} m through walls[{j}] "
                    f"('{w.name}', a plane) to its back side; particles placed there are pushed "
                    f"through the wall or lost: keep the region on the side normal points to")


def _extent(region, n) -> float:
    """Half extent of a sphere or cylinder region along the unit vector ``n``."""
    r = float(region.radius)
    if region.kind == "sphere":
        return r
    c = float(abs(_axis(region) @ n))
    return 0.5 * float(region.length) * c + r * math.sqrt(max(0.0, 1.0 - c * c))


def check_monitor_regions(case) -> None:
    """A monitor region wholly outside the domain box samples nothing."""
    dlo, dhi = np.asarray(case.dem.domain_lo, float), np.asarray(case.dem.domain_hi, float)
    for i, m in enumerate(case.monitors):
        if m.region is None:
            continue
        lo, hi = _region_box(m.region)
        if (hi < dlo).any() or (lo > dhi).any():
            raise GsiInputError(
                f"monitors[{i}].region: {np.round(lo, 9).tolist()} to "
                f"{np.round(hi, 9).tolist()} lies outside dem.domain ({dlo.tolist()} to "
                f"{dhi.tolist()}); it would sample no particle: move it (m)")


def _resting_conductance(case, i: int) -> tuple[float, float]:
    """(H, m c_p / s) of the smallest particle of source i in one contact under its own
    weight: a lower bound of the conductance sum of any particle at rest (which carries
    at least its weight through at least one contact). Hertz with F = m g:
    a = (3 F R*/(4 E*))^(1/3) (Johnson, eq. 4.22), R* = r/2, E* = E/(2(1-nu^2));
    ``area`` H = 2 k sqrt(pi) a, ``radius`` H = 2 k a, ``constant`` H = h_c (heat.py)."""
    p = case.particles[i]
    mat = case.materials[p.material]
    r = case.source_smallest_radius(i)
    m = mat.rho * 4.0 / 3.0 * math.pi * r ** 3
    mc = m * mat.cp / case.run.heat_time_scale
    model = case.dem.heat
    if model == "constant":
        return case.dem.h_c, mc
    g = float(np.linalg.norm(case.dem.gravity))
    if model not in ("area", "radius") or g == 0 or case.dem.contact != "hertz":
        return 0.0, mc
    e_star = mat.E / (2.0 * (1.0 - mat.nu ** 2))
    a = (3.0 * m * g * 0.5 * r / (4.0 * e_star)) ** (1.0 / 3.0)
    H = 2.0 * mat.k * a * (math.sqrt(math.pi) if model == "area" else 1.0)
    return H, mc


def check_heat_stability(case, dt: float) -> None:
    """The explicit heat update T += dt Q/(m c_p) is unstable when dt sum_j H_ij/(m_i c_p,i)
    exceeds 1 (the bound the run checks at every neighbour rebuild). A particle at rest
    has at least one contact carrying its weight, so the ratio of one such contact is a
    lower bound: above 1 the run would stop; refused here with the case's keys (unless
    ``dem.force_dt``)."""
    if case.dem.heat == "none" or case.dem.force_dt:
        return
    for i in range(len(case.particles)):
        H, mc = _resting_conductance(case, i)
        ratio = dt * H / mc if mc > 0 else 0.0
        if ratio > 1.0:
            s = case.run.heat_time_scale
            fix = (f"lower run.heat_time_scale to <= {s / ratio:.3g}" if s > 1 else
                   f"use run.dt <= {dt / ratio:.3g} s")
            key = (f"run.heat_time_scale = {s:g}" if s > 1 else
                   f"dem.h_c = {case.dem.h_c:g}" if case.dem.heat == "constant" else
                   f"run.dt = {dt:.3g}")
            raise GsiInputError(
                f"{key}: the explicit heat update is unstable: dt H/(m "
                f"c_p/s) = {ratio:.3g} > 1 already for one resting contact of particles[{i}] "
                f"(dem.heat = '{case.dem.heat}', dt = {dt:.3g} s); {fix} (or dem.force_dt = "
                f"true to run anyway)")


#: most site-triangle pairs the lattice check computes (beyond: checked on a sample)
MAX_PAIRS = 20_000_000


def check_lattices_against_walls(case) -> None:
    """Particles placed at the start closer to a shaped wall (cone, funnel, cylinder,
    drum, plate, mesh) than their radius: they would start cut by the wall and be pushed
    through it or lost. Lattice sites (within 0.999 of the largest radius), a particle
    file's rows (within (1 - MAX_OVERLAP) of their radius), and a random fill's or a
    stream's possible centres (:func:`gsi.case.structure_checks.possible_centres`: within
    (1 - MAX_OVERLAP) of the smallest radius: the region reaches through the wall)."""
    from gsi.case.sources import MAX_OVERLAP, read_particle_file
    from gsi.case.structure_checks import possible_centres
    shaped = [(j, w) for j, w in enumerate(case.walls) if w.kind not in ("plane", "box")]
    if not shaped:
        return
    for i, p in enumerate(case.particles):
        if p.fill == "lattice":
            x = p.lattice_sites(f"particles[{i}]")
            r = np.full(len(x), 0.999 * p.size.largest)
        elif p.fill == "file":
            data = read_particle_file(case.base_dir / p.file, key=f"particles[{i}].file",
                                      shown=p.file)
            x, r = data["x"], (1.0 - MAX_OVERLAP) * data["radius"]
        else:
            r0 = case.source_smallest_radius(i)
            x = possible_centres(p, r0)
            r = np.full(len(x), (1.0 - MAX_OVERLAP) * r0)
        for j, w in shaped:
            V, T = w.surface(base_dir=case.base_dir)
            hit = _nearest_within(x, r, V, T)
            if hit is None:
                continue
            k, d = hit
            if p.fill == "lattice":
                what = (f"particles[{i}].region: lattice sites cross walls[{j}] ('{w.name}', "
                        f"a {w.kind}): the site at")
                less = f"less than the radius {p.size.largest:g} m"
            elif p.fill == "file":
                what = (f"particles[{i}].file = '{p.file}': row {k} cuts walls[{j}] "
                        f"('{w.name}', a {w.kind}): the row at")
                less = f"less than its radius {r[k] / (1.0 - MAX_OVERLAP):g} m"
            else:
                what = (f"particles[{i}].region: reaches through walls[{j}] ('{w.name}', a "
                        f"{w.kind}): the possible centre at")
                less = f"less than the smallest radius {r[k] / (1.0 - MAX_OVERLAP):g} m"
            raise GsiInputError(f"{what} {np.round(x[k], 6).tolist()} is {d:.3g} m from it, "
                                f"{less}; shrink or move the "
                                f"{'particles' if p.fill == 'file' else 'region'} inside the wall")


def _nearest_within(x, r, V, T):
    """(index, distance) of the point of ``x`` nearest the triangles (V, T) relative to its
    limit ``r``, among those closer than their limit; None if none is. Points beyond the
    triangles' box are skipped; above MAX_PAIRS point-triangle pairs a sample is checked."""
    lo, hi = V.min(0) - r.max(), V.max(0) + r.max()
    idx = np.flatnonzero(((x >= lo) & (x <= hi)).all(1))
    if len(idx) == 0:
        return None
    idx = idx[::max(1, int(len(idx) * len(T) // MAX_PAIRS) + 1)]
    chunk = max(1, 2_000_000 // len(T))       # bounded temporary arrays
    for k in range(0, len(idx), chunk):
        sel = idx[k:k + chunk]
        d = point_triangle_distance(x[sel], V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]).min(1)
        bad = d < r[sel]
        if bad.any():
            m = int(np.argmin(np.where(bad, d / r[sel], np.inf)))
            return int(sel[m]), float(d[m])
    return None


#: the largest particle-particle friction coefficient at which the Coulomb cap bounds the
#: tangential (rotational) mode below: the drum demo at dt = 0.23 t_R ran with mu = 1, 3
#: and 10 and blew up with mu = 30 (step 449) and 100 (step 413)
MU_CAPPED = 10.0


def check_friction_stability(case, dt: float) -> None:
    """A very high sliding friction (mu > MU_CAPPED) removes the Coulomb cap that bounds
    the stiffest mode of a packed bed: the counter-rotation of neighbours whose contacts
    stick. A sphere with four sticking contacts about an axis turns against a rotational
    stiffness 8 k_t R^2 (each contact point moves 2 R omega relative to its neighbour), so
    omega_rot = sqrt(8 k_t R^2 / I) = sqrt(20 k_t / m) with I = 2/5 m R^2: about 2.9 x the
    normal frequency sqrt(S_n/m*) of a pair (k_t = 8 G* a, S_n = 2 E* a). Its damping
    ratio zeta = 10 gamma_t/(m omega_rot) (gamma_t of the Hertz-Mindlin law) is above
    1, and an explicit step with the damping force from the current velocity is stable
    only for omega dt < 2 (sqrt(1 + zeta^2) - zeta). Evaluated at the contact carrying a
    column of particles over the domain's height (Hertz, Johnson eq. 4.22); beyond it the
    case is refused, naming the friction key, unless ``dem.force_dt``."""
    if case.dem.contact != "hertz" or case.dem.force_dt:
        return
    from gsi.dem.materials import beta_of_e
    pairs = {frozenset(p.materials): (j, p) for j, p in enumerate(case.pairs)}
    g = float(np.linalg.norm(case.dem.gravity))
    height = max(case.dem.domain_size, 0.0)
    for i, p in enumerate(case.particles):
        mat = case.materials[p.material]
        j, pair = pairs.get(frozenset((p.material,)), (None, None))
        mu = pair.mu if pair is not None and pair.mu is not None else mat.mu
        if mu <= MU_CAPPED:
            continue
        e = pair.e if pair is not None and pair.e is not None else mat.e
        key = f"pairs[{j}].mu" if pair is not None and pair.mu is not None else \
            f"materials.{p.material}.mu"
        r = case.source_smallest_radius(i)
        m = mat.rho * 4.0 / 3.0 * math.pi * r ** 3
        e_star = mat.E / (2.0 * (1.0 - mat.nu ** 2))
        g_star = mat.E / (4.0 * (2.0 - mat.nu) * (1.0 + mat.nu))
        force = max(1.0, height / (2.0 * r)) * m * max(g, 1e-12)
        delta = (3.0 * force / (4.0 * e_star * math.sqrt(0.5 * r))) ** (2.0 / 3.0)
        a = math.sqrt(0.5 * r * delta)
        s_n, k_t = 2.0 * e_star * a, 8.0 * g_star * a
        gamma_t = 2.0 * math.sqrt(5.0 / 6.0) * abs(beta_of_e(e)) * math.sqrt(s_n * 0.5 * m) \
            * math.sqrt(k_t / s_n)
        omega = math.sqrt(20.0 * k_t / m)
        zeta = 10.0 * gamma_t / (m * omega)
        limit = 2.0 * (math.sqrt(1.0 + zeta * zeta) - zeta)
        if omega * dt > limit:
            raise GsiInputError(
                f"{key} = {mu:g}: above {MU_CAPPED:g} the Coulomb cap no longer bounds the "
                f"sticking contacts of particles[{i}], and the counter-rotation of neighbours (frequency sqrt(20 k_t/m) = "
                f"{omega:.3g} rad/s, damping ratio {zeta:.2f}) is unstable at dt = {dt:.3g} s "
                f"(stable below {limit / omega:.3g} s); use run.dt <= {0.9 * limit / omega:.3g} "
                f"or mu <= {MU_CAPPED:g} (or dem.force_dt = true to run anyway)")


def check_geometry(case) -> None:
    """The geometric contradictions (planes and fills, monitor regions, lattices and walls,
    structures outside the domain or through the particles)."""
    check_lengths(case)
    check_planes_and_fills(case)
    check_monitor_regions(case)
    check_lattices_against_walls(case)
    check_structures(case)


def check_stability(case, dt: float) -> None:
    """The stability bounds known before the run (heat update, very high friction, a
    servo wall's gain: :func:`gsi.case.driven_motion.check_servo_gains`)."""
    from gsi.case.driven_motion import check_servo_gains
    check_heat_stability(case, dt)
    check_friction_stability(case, dt)
    check_servo_gains(case, dt)


def check_lengths(case) -> None:
    """Every scalar length of the case (a key of unit m, and a builder's geometry number)
    within 100 x the domain's diagonal: beyond it is a unit slip ("did you give mm?")."""
    import dataclasses
    dlo, dhi = np.asarray(case.dem.domain_lo, float), np.asarray(case.dem.domain_hi, float)
    size = float(np.linalg.norm(dhi - dlo))

    def refuse(key, v):
        raise GsiInputError(f"{key} = {v:g}: over 100 x the domain's diagonal ({size:.3g} m); "
                            f"did you give mm? lengths are in m")

    def walk(obj, path):
        for f in dataclasses.fields(obj):
            if not f.init:
                continue
            v = getattr(obj, f.name)
            key = f"{path}.{f.name}" if path else f.name
            if dataclasses.is_dataclass(v):
                walk(v, key)
            elif isinstance(v, list) and v and dataclasses.is_dataclass(v[0]):
                for i, item in enumerate(v):
                    walk(item, f"{key}[{i}]")
            elif isinstance(v, dict) and v and all(dataclasses.is_dataclass(x) for x in v.values()):
                for k, item in v.items():
                    walk(item, f"{key}.{k}")
            elif (f.metadata.get("unit") == "m" and isinstance(v, float)
                  and abs(v) > 100.0 * size):
                refuse(key, v)
    walk(case, "")
    for i, st in enumerate(case.structures):
        if st.mesh is None:
            continue
        for k, v in st.geometry.items():
            if isinstance(v, float) and abs(v) > 100.0 * size:
                refuse(f"structures[{i}].geometry.{k}", v)
