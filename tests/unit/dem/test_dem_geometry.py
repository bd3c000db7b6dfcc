"""Closest point on a triangle: regions and barycentric weights against brute force."""
import numpy as np
import pytest

from gsi.dem.geometry import closest_point_triangle, FACE, VA, VB, VC, EAB, EBC, ECA

A, B, C = np.array([0.0, 0, 0]), np.array([1.0, 0, 0]), np.array([0.0, 1, 0])


def cpt(p):
    return closest_point_triangle(*p, *A, *B, *C)


@pytest.mark.parametrize("p,region", [
    ((0.2, 0.2, 0.5), FACE), ((-0.5, -0.5, 0.1), VA), ((2.0, -0.1, 0.0), VB),
    ((-0.1, 2.0, 0.3), VC), ((0.5, -1.0, 0.2), EAB), ((1.0, 1.0, -0.4), EBC),
    ((-1.0, 0.5, 0.0), ECA)])
def test_regions(p, region):
    qx, qy, qz, wa, wb, wc, reg = cpt(p)
    assert reg == region
    q = np.array([qx, qy, qz])
    np.testing.assert_allclose(wa * A + wb * B + wc * C, q, atol=1e-15)
    assert min(wa, wb, wc) >= 0 and wa + wb + wc == pytest.approx(1.0)


def test_matches_brute_force():
    rng = np.random.default_rng(0)
    s = np.linspace(0, 1, 201)
    u, v = np.meshgrid(s, s)
    keep = u + v <= 1
    pts = A + u[keep, None] * (B - A) + v[keep, None] * (C - A)
    for p in rng.normal(0.3, 1.0, (50, 3)):
        qx, qy, qz, *_ = cpt(p)
        d_exact = np.linalg.norm(np.array([qx, qy, qz]) - p)
        d_brute = np.linalg.norm(pts - p, axis=1).min()
        assert d_exact <= d_brute + 1e-12
        assert d_brute - d_exact < 1e-2
