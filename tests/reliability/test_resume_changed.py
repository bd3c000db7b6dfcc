"""``gsi run --resume`` of a case changed since its checkpoint (the fingerprint in every
manifest, :mod:`gsi.case.fingerprint`): refused with the changed keys; with
``--allow-changes`` it continues and prints what changed."""
import importlib.util
import pathlib

_spec = importlib.util.spec_from_file_location(
    "gsi_tests_reliability_util", pathlib.Path(__file__).resolve().parent / "_util.py")
_util = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_util)


def test_resume_of_a_changed_case_needs_allow_changes(tmp_path):
    first = _util.driver(tmp_path / "first", "--checkpoint-every", _util.EVERY, check=False)
    assert first.returncode == 0, first.stderr[-3000:]
    step = _util.rewind(tmp_path / "first", tmp_path / "out")
    changed = tmp_path / "case" / _util.CASE.name
    changed.parent.mkdir()
    text = _util.CASE.read_text()
    assert "\nmu = 0.5\n" in text
    changed.write_text(text.replace("\nmu = 0.5\n", "\nmu = 0.8\n", 1))
    proc = _util.cli(tmp_path / "out", "--resume", case=changed)
    out, err = proc.communicate(timeout=600)
    assert proc.returncode == 2, err[-2000:]
    assert err.startswith("error: --resume: the case changed since the checkpoint at t = ")
    assert "materials.ore.mu: 0.5 -> 0.8" in err and len(err.splitlines()) == 1
    proc = _util.cli(tmp_path / "out", "--resume", "--allow-changes", case=changed)
    out, err = proc.communicate(timeout=600)
    assert proc.returncode == 0, err[-3000:]
    said = [ln for ln in err.splitlines() if ln.startswith("warning: --allow-changes")]
    assert said and "1 changed key(s): materials.ore.mu: 0.5 -> 0.8" in said[0], err
    assert f"(step {step})" in out
