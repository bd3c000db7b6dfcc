"""Every case shipped under demos/ (graded cases included) passes ``gsi check``, and a
``fixed = true`` particle source holds its particles (seed 001 case 4's overlapping pair)."""
import pathlib

import numpy as np
import pytest

from gsi.case import load_case
from gsi.errors import GsiInputError

ROOT = pathlib.Path(__file__).resolve().parents[3]
SHIPPED = sorted((ROOT / "demos").rglob("*.toml"))


def test_there_are_shipped_cases():
    assert len(SHIPPED) >= 17


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: str(p.relative_to(ROOT / "demos")))
def test_shipped_case_passes_check(path):
    case = load_case(path)
    assert case.check() > 0


def test_fixed_source_is_held_and_may_overlap():
    from gsi.run import build_simulation
    case = load_case(ROOT / "demos" / "graded" / "case4_two_particles.toml")
    assert case.particles[0].fixed
    sim, _, groups = build_simulation(case, dt=case.check())
    ids = groups["pair"]
    assert len(ids) == 2
    assert np.all(sim.particles.fixed[sim.index(ids)] == 1)


def test_fixed_overlap_is_refused_without_fixed():
    case = load_case(ROOT / "demos" / "graded" / "case4_two_particles.toml")
    case.particles[0].fixed = False
    with pytest.raises(GsiInputError, match="overlap by 0.1 x the smaller radius"):
        case.check()


def test_a_stream_cannot_be_fixed():
    from gsi.case import ParticleSource, Region, Size
    src = ParticleSource(material="glass", fill="stream", rate=10.0, fixed=True,
                         size=Size(kind="single", radius=0.01),
                         region=Region(kind="sphere", centre=(0.0, 0.0, 0.0), radius=0.1))
    with pytest.raises(GsiInputError, match="fixed"):
        src.validate()
