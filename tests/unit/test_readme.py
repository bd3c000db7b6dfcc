"""The README stays true: its worked examples make one case that ``gsi check`` accepts,
and its key list is what ``gsi check --keys`` prints (regenerate with that command)."""
import pathlib
import re
import tomllib

from gsi.case import Case, case_from_table
from gsi.config.schema import describe

ROOT = pathlib.Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()


def _between(tag):
    m = re.search(rf"<!-- {tag}:start -->(.*?)<!-- {tag}:end -->", README, re.S)
    assert m, f"README has no {tag} section"
    return m.group(1)


def test_worked_examples_make_one_valid_case():
    blocks = re.findall(r"```toml\n(.*?)```", _between("case-examples"), re.S)
    assert len(blocks) >= 6
    table = tomllib.loads("\n".join(blocks))
    case = case_from_table(table, base_dir=ROOT / "demos")
    assert case.check() == 1.0e-4
    kinds = {w.kind for w in case.walls} | {p.fill for p in case.particles} | \
        {m.kind for m in case.monitors}
    assert {"plane", "mesh", "cone", "plate", "random", "stream", "file", "wall", "discharge",
            "temperature", "structure"} <= kinds
    assert {s.name for s in case.structures} == {"belt", "membrane"}
    assert case.quick_variant().run.duration == 0.2


def test_key_list_is_what_gsi_check_keys_prints():
    block = _between("case-keys")
    lines = block.strip().strip("`").strip("\n").splitlines()
    assert lines == describe(Case)
