"""The [extrapolation] table: bad input is refused with one line naming the key, the
drum family's case passes ``gsi check``, and the runner's event steps."""
import pathlib
import tomllib

import pytest

from gsi.case import case_from_table, case_to_table
from gsi.studies.drum import drum_case, drum_geometry
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


def kiln_table(**over):
    from gsi.studies.kiln import kiln_case, kiln_geometry
    t = case_to_table(kiln_case(kiln_geometry(300), periods=20, compare_periods=3))
    for key, value in over.items():
        path = key.split("__")
        d = t
        for p in path[:-1]:
            d = d[int(p)] if p.isdigit() else d[p]
        d[path[-1]] = value
    return t


def test_kiln_case_passes_the_checks():
    case = case_from_table(kiln_table())
    assert case.check() == 1e-4
    assert case.extrapolation.n_compare == 3
    assert case.extrapolation.end() == pytest.approx(case.run.duration)
    assert case.structures[0].contact.motion.rotates


@pytest.mark.parametrize("over,message", [
    ({"extrapolation__compare_periods": 30},
     r"extrapolation.compare_periods = 30: more than periods = 20"),
    ({"extrapolation__compare_periods": 0}, r"extrapolation.compare_periods = 0: must be > 0"),
    ({"run__duration": 2.0}, r"run.duration = 2.0: shorter than t1 \+ compare_periods x "),
    ({"extrapolation__period": 0.6}, r"extrapolation.period = 0.6: must be a whole number "
                                     r"of coupling intervals"),
    ({"extrapolation__start": 1.1}, r"extrapolation.start = 1.1: must be a whole number "),
    ({"structures__0__contact__mode": "both"},
     r"structures\[0\].contact.motion: only with contact.mode = 'thermal'"),
    ({"structures__0__contact__motion": {"kind": "translation", "velocity": [0.1, 0, 0]}},
     r"structures\[0\].contact.motion.kind = 'translation': the wall of an FE structure "
     r"may only turn"),
    ({"structures__0__contact__motion": {"kind": "rotation", "rpm": 30.0}},
     r"structures\[0\].contact.motion.axis: missing"),
])
def test_bad_kiln_input(over, message):
    with pytest.raises(GsiInputError, match=message):
        case_from_table(kiln_table(**over)).check()


def test_extrapolation_refuses_a_mechanical_structure():
    t = kiln_table()
    t["structures"][0]["contact"].pop("motion")
    t["structures"][0]["contact"]["mode"] = "both"
    with pytest.raises(GsiInputError, match=r"structures\[0\].contact.mode = 'both': the "
                                            r"extrapolation replays heat only"):
        case_from_table(t).check()
    t["structures"].append(dict(t["structures"][0], name="other"))
    with pytest.raises(GsiInputError, match=r"extrapolation: 2 \[\[structures\]\]"):
        case_from_table(t).check()


def test_kiln_demo_toml_reads():
    t = tomllib.loads((ROOT / "demos" / "kiln.toml").read_text())
    case = case_from_table(t)
    assert case.check() == 1e-4
    assert case.quick_variant().extrapolation.periods == 3600
