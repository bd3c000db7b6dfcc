"""The contact model (gsi.dem.contact.model): sub-models by name over lanes, one
evaluation site for pairs, planes and triangles, and each normal law against its formula
(docs/design.md, "DEM physics")."""
import ast
import math
import pathlib

import numpy as np
import pytest

import gsi
from gsi.dem.contact import lanes as L
from gsi.dem.contact.model import model_ids, evaluate, NORMAL, HEAT, ROLLING
from gsi.dem.materials import Material, pair_table
from gsi.errors import GsiInputError

GSI = pathlib.Path(gsi.__file__).parent
MAT = Material(E=7e7, nu=0.25, rho=2500.0, e=0.6, mu=0.4, mu_r=0.05, k=1.5)


def _buffer(n, rng):
    """A lane buffer of n contacts with random geometry, no spring yet."""
    B = np.zeros(L.NB * L.CH)
    nrm = rng.normal(size=(n, 3))
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    f = {L.NX: nrm[:, 0], L.NY: nrm[:, 1], L.NZ: nrm[:, 2],
         L.DELTA: rng.uniform(1e-7, 2e-5, n), L.VX: rng.normal(0, 0.1, n),
         L.VY: rng.normal(0, 0.1, n), L.VZ: rng.normal(0, 0.1, n),
         L.REFF: rng.uniform(5e-4, 1e-3, n), L.MEFF: rng.uniform(1e-6, 1e-5, n),
         L.IEFF: rng.uniform(1e-13, 1e-12, n), L.WX: rng.normal(0, 5, n),
         L.WY: rng.normal(0, 5, n), L.WZ: rng.normal(0, 5, n),
         L.A2: rng.uniform(1e-9, 1e-8, n), L.RI: np.full(n, 1e-3), L.RJ: np.full(n, 1e-3),
         L.DTEMP: rng.normal(0, 10, n)}
    for off, val in f.items():
        B[int(off):int(off) + n] = val
    return B


def _get(B, off, n):
    return B[int(off):int(off) + n]


@pytest.mark.parametrize("normal", ["hertz", "linear"])
def test_normal_and_tangential_laws_match_their_formulas(normal):
    """F_n, the first-step tangential force with its Coulomb cap, the CDT torque and the
    area conductance of every lane, against the formulas written out here in numpy."""
    rng = np.random.default_rng(3)
    n, dt, k_n = 50, 1e-6, 2e3
    table = pair_table([MAT], k_n=k_n)
    tab = table.reshape(1, -1)
    B = _buffer(n, rng)
    evaluate(0, n, B, tab, 0, dt, model_ids(normal, "history", "cdt", "area"))
    g = lambda off: _get(B, off, n)   # noqa: E731
    nvec = np.column_stack([g(L.NX), g(L.NY), g(L.NZ)])
    v = np.column_stack([g(L.VX), g(L.VY), g(L.VZ)])
    d, R, m = g(L.DELTA), g(L.REFF), g(L.MEFF)
    E_s = 1 / (2 * (1 - MAT.nu ** 2) / MAT.E)
    G_s = 1 / (2 * 2 * (2 - MAT.nu) * (1 + MAT.nu) / MAT.E)
    beta = math.log(MAT.e) / math.sqrt(math.log(MAT.e) ** 2 + math.pi ** 2)
    v_n = np.sum(v * nvec, axis=1)
    if normal == "hertz":
        S_n = 2 * E_s * np.sqrt(R * d)
        F_n = 4 / 3 * E_s * np.sqrt(R * d) * d - 2 * math.sqrt(5 / 6) * beta * np.sqrt(S_n * m) * v_n
        k_t = 8 * G_s * np.sqrt(R * d)
        g_t = -2 * math.sqrt(5 / 6) * beta * np.sqrt(k_t * m)
    else:
        F_n = k_n * d - 2 * beta * np.sqrt(k_n * m) * v_n
        k_t = 2 / 7 * k_n
        g_t = -2 * beta * np.sqrt(k_t * m)
    np.testing.assert_allclose(g(L.FN), F_n, rtol=1e-12)
    v_t = v - v_n[:, None] * nvec
    k_t = np.broadcast_to(k_t, n)[:, None]
    g_t = np.broadcast_to(g_t, n)[:, None]
    F_t = -k_t * v_t * dt - g_t * v_t
    cap = MAT.mu * np.abs(F_n)
    mag = np.linalg.norm(F_t, axis=1)
    F_t = np.where((mag > cap)[:, None], F_t * (cap / mag)[:, None], F_t)
    F = -F_n[:, None] * nvec + F_t
    np.testing.assert_allclose(np.column_stack([g(L.FX), g(L.FY), g(L.FZ)]), F,
                               rtol=1e-10, atol=1e-12 * np.abs(F).max())
    assert 0 < np.sum(mag > cap) < n, "the lanes should include sliding and sticking ones"
    w = np.column_stack([g(L.WX), g(L.WY), g(L.WZ)])
    wn = np.linalg.norm(w, axis=1)
    M = np.minimum(MAT.mu_r * R * np.abs(F_n), wn * g(L.IEFF) / dt)
    np.testing.assert_allclose(np.column_stack([g(L.MX), g(L.MY), g(L.MZ)]),
                               -(M / wn)[:, None] * w, rtol=1e-12)
    H = 4 * MAT.k * MAT.k / (2 * MAT.k) * np.sqrt(math.pi * g(L.A2))
    np.testing.assert_allclose(g(L.Q), H * g(L.DTEMP), rtol=1e-12)


def test_sub_models_by_name():
    """Names select registry entries; rolling and heat switch off to zero torque and heat."""
    ids = model_ids("linear", "history", True, None, log=True)
    assert list(ids) == [list(NORMAL).index("linear"), 0, list(ROLLING).index("cdt"),
                         list(HEAT).index("none"), 1, 0]
    rng = np.random.default_rng(1)
    B = _buffer(10, rng)
    evaluate(0, 10, B, pair_table([MAT]).reshape(1, -1), 0, 1e-6, model_ids("hertz"))
    assert not _get(B, L.MX, 10).any() and not _get(B, L.Q, 10).any()
    for kw, key in [({"normal": "hooke"}, "contact"), ({"heat": "areas"}, "heat"),
                    ({"rolling": "epsd"}, "rolling")]:
        with pytest.raises(GsiInputError, match=key):
            model_ids(**kw)


def _calls(tree):
    """{function name: names of the functions it calls} of a module's AST."""
    out = {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            out[node.name] = {c.func.id for c in ast.walk(node)
                              if isinstance(c, ast.Call) and isinstance(c.func, ast.Name)}
    return out


def test_one_evaluation_site_for_pairs_planes_and_triangles():
    """The contact model is evaluated at one place in the engine, which both the pair path
    and the wall path (planes and triangles) call; only the registry imports the laws."""
    calls = {}
    for name in ("engine.py", "pair_lanes.py", "wall_lanes.py"):
        calls.update(_calls(ast.parse((GSI / "dem" / name).read_text())))
    assert {f for f, c in calls.items() if "evaluate" in c} == {"evaluate_runs"}
    assert {f for f, c in calls.items() if "evaluate_runs" in c} == {"finish_pairs",
                                                                     "finish_walls"}
    for f in ("gather_pairs", "finish_pairs", "gather_planes", "gather_triangles",
              "finish_walls"):
        assert f in calls["slab_task"]
    law_modules = {"gsi.dem.contact.hertz", "gsi.dem.contact.linear",
                   "gsi.dem.contact.tangential", "gsi.dem.contact.rolling"}
    importers = set()
    for f in GSI.rglob("*.py"):
        for node in ast.walk(ast.parse(f.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module:
                names = {f"{node.module}.{a.name}" for a in node.names} | {node.module}
                if names & law_modules:
                    importers.add(f.relative_to(GSI).as_posix())
    assert importers == {"dem/contact/model.py"}
