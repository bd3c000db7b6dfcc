"""The [extrapolation] table: bad input is refused with one line naming the key, the
drum family's case passes ``gsi check``, and the runner's event steps."""
import pathlib
import tomllib

import pytest

from gsi.case import case_from_table, case_to_table
from gsi.drum import drum_case, drum_geometry
from gsi.errors import GsiInputError
from gsi.extrapolation import CaseExtrapolation

ROOT = pathlib.Path(__file__).resolve().parents[3]


def table(**over):
    t = case_to_table(drum_case(drum_geometry(640), settle=0.5, extrapolation=True,
                                spin_up=0.25, period_turns=0.25))
    for key, value in over.items():
        section, _, name = key.partition("__")
        t[section][name] = value
    return t


def test_drum_case_passes_the_checks():
    case = case_from_table(table())
    assert case.check() == 1e-4
    assert case.extrapolation.end() == pytest.approx(case.run.duration)


@pytest.mark.parametrize("over,message", [
    ({"run__duration": 3.0}, r"run.duration = 3.0: shorter than t1 \+ periods x period"),
    ({"dem__heat": "none"}, r"dem.heat = 'none': the extrapolation replays the contacts"),
    ({"dem__heat": "pipe", "dem__pipe_length": 0.01}, r"dem.heat = 'pipe': the extrapolation"),
    ({"extrapolation__dt_split": 0.0015}, r"extrapolation.dt_split = 0.0015: must be a "
                                          r"multiple of every x run.dt = 0.001 s"),
    ({"extrapolation__period": 0.005}, r"extrapolation.period = 0.005: shorter than 10 samples"),
    ({"extrapolation__halves": {"t": 5.0, "below": 30.0, "above": 10.0}},
     r"extrapolation.halves.t = 5.0: after extrapolation.start"),
    ({"extrapolation__every": 0}, r"extrapolation.every = 0: must be > 0"),
    ({"extrapolation__halves": {"t": 0.5, "axis": "w", "below": 30.0, "above": 10.0}},
     r"extrapolation.halves.axis = 'w': must be one of"),
])
def test_bad_extrapolation_input(over, message):
    with pytest.raises(GsiInputError, match=message):
        case_from_table(table(**over)).check()


def test_event_steps(tmp_path):
    case = case_from_table(table())
    xp = CaseExtrapolation(case.extrapolation, dt=1e-4, out=tmp_path)
    K = drum_geometry(640).steps_per_turn // 4
    k0 = 5000 + K
    assert xp.steps == [5000, k0, k0 + K] + [k0 + K * (1 + p) for p in range(1, 7)]
    assert xp.steps[-1] == round(case.run.duration / 1e-4)


def test_demo_toml_reads():
    t = tomllib.loads((ROOT / "demos" / "drum_extrapolation.toml").read_text())
    case = case_from_table(t)
    assert case.extrapolation.every == 10 and case.extrapolation.halves.below == 30.0
