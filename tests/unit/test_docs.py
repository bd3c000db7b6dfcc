"""The documentation's examples stay true: the tutorial's case passes ``gsi check`` and
its Python twin is the same case; every TOML block of the docs parses; the design notes
keep the section names that docstrings cite (``docs/design.md, "Section"``)."""
import importlib.util
import pathlib
import re
import tomllib

import pytest

from gsi.case import case_to_table, load_case
from gsi.case.case import validated

ROOT = pathlib.Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"


def test_tutorial_case_passes_check():
    case = load_case(DOCS / "tutorial" / "silo.toml")
    assert case.check() > 0
    assert case.structures[0].file == "silo.geo"


def test_tutorial_python_is_the_toml_case():
    spec = importlib.util.spec_from_file_location("silo_study", DOCS / "tutorial" / "silo_study.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert case_to_table(validated(mod.case)) == case_to_table(load_case(DOCS / "tutorial" / "silo.toml"))
    # Janssen: no friction limit -> all weight on the bottom; the wall's share grows with depth
    assert mod.janssen_wall_load(1500.0, 0.08, 1e-6, 0.3, 0.5) == pytest.approx(0.0, abs=1e-9)
    assert 0 < mod.janssen_wall_load(1500.0, 0.08, 0.05, 0.3, 0.5) < \
        mod.janssen_wall_load(1500.0, 0.08, 0.1, 0.3, 0.5)


@pytest.mark.parametrize("page", sorted(p.name for p in DOCS.glob("*.md")))
def test_toml_blocks_parse(page):
    for block in re.findall(r"```toml\n(.*?)```", (DOCS / page).read_text(), re.S):
        tomllib.loads(block)


def test_design_sections_cited_by_docstrings_exist():
    headings = {h.strip() for h in re.findall(r"^#+ (.*)$", (DOCS / "design.md").read_text(), re.M)}
    for name in ("DEM physics", "Contact geometry", "Heat in particles", "Structure (FE) physics",
                 "Thermo-elastic", "Coupling", "Balance", "Validation cases",
                 "Long-time heat extrapolation"):
        assert name in headings, name


def _check_site():
    spec = importlib.util.spec_from_file_location("check_site", DOCS / "check_site.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_site_check_finds_broken_links_images_and_anchors(tmp_path):
    site = tmp_path / "html"
    (site / "sub").mkdir(parents=True)
    (site / "pic.png").write_bytes(b"\x89PNG")
    (site / "index.html").write_text(
        '<a href="sub/page.html#here">ok</a><img src="pic.png"><a href="https://x.org/">ext</a>'
        '<a href="missing.html">broken</a><img src="gone.png"><a href="sub/page.html#nope">x</a>')
    (site / "sub" / "page.html").write_text('<h1 id="here">t</h1><a href="../index.html">up</a>')
    problems = _check_site().check_links(site)
    assert len(problems) == 3, problems
    assert any("missing.html" in p for p in problems)
    assert any("gone.png" in p for p in problems)
    assert any("'nope'" in p for p in problems)


def _gsi_docs():
    spec = importlib.util.spec_from_file_location("gsi_docs", DOCS / "_ext" / "gsi_docs.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_key_reference_is_what_gsi_check_keys_prints():
    from gsi.case import Case
    from gsi.config.schema import describe
    page = _gsi_docs().keys_page()
    for line in describe(Case):
        assert line in page


def test_validation_page_says_when_results_are_missing(tmp_path, monkeypatch):
    mod = _gsi_docs()
    monkeypatch.setattr(mod, "ROOT", tmp_path)
    assert "No results file" in mod.validation_page()
    (tmp_path / "tests" / "validation").mkdir(parents=True)
    (tmp_path / "tests" / "validation" / "results.json").write_text(
        '{"records": [{"name": "restitution", "test": "tests/validation/t.py::a", '
        '"reference": 0.5, "measured": 0.4999, "tolerance": 0.01, "kind": "rel", '
        '"outcome": "passed", "date": "d", "host": "h", "commit": "c"}]}')
    page = mod.validation_page()
    assert "| restitution | 0.5 | 0.4999 | -2.00e-04 (rel.) | 0.01 (rel) |  | passed |" in page
    # a paper's goal beside the bound (shown, not asserted)
    (tmp_path / "tests" / "validation" / "results.json").write_text(
        '{"records": [{"name": "eq. 10", "test": "tests/validation/t.py::a", '
        '"reference": 0.15, "measured": 0.09, "tolerance": 0.15, "kind": "bound", '
        '"goal": "seed 003: <= 5 %", "outcome": "passed", "date": "d", "host": "h", '
        '"commit": "c"}]}')
    assert "| 0.15 (bound) | seed 003: <= 5 % | passed |" in mod.validation_page()


def test_literate_demo_becomes_prose_and_code():
    md = _gsi_docs().literate_to_markdown("# # Title\n#\n# Some prose.\n\nx = 1\n\n# ## Step\ny = 2\n")
    assert md.split("\n")[:3] == ["# Title", "", "Some prose."]
    assert "```python\nx = 1\n```" in md and "## Step" in md and "```python\ny = 2\n```" in md


def test_benchmark_record_appends_the_last_key_value_line(tmp_path, monkeypatch):
    spec = importlib.util.spec_from_file_location("record", ROOT / "benchmarks" / "record.py")
    rec = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(rec)
    assert rec.parse_last_line("warming up\nn=3 rate=1.5e7 solver=direct\n(done)\n") == \
        {"n": 3, "rate": 1.5e7, "solver": "direct"}
    monkeypatch.setattr(rec, "RESULTS", tmp_path)
    import sys
    code = rec.main(["demo", "--", sys.executable, "-c", "print('x'); print('a=1 b=2.5')"])
    assert code == 0
    import json
    data = json.loads((tmp_path / "demo.json").read_text())
    assert data["records"][-1]["figures"] == {"a": 1, "b": 2.5}
    assert data["records"][-1]["date"] and data["records"][-1]["host"]


def test_benchmark_results_are_well_formed():
    import json
    for f in (ROOT / "benchmarks" / "results").glob("*.json"):
        data = json.loads(f.read_text())
        assert data["records"], f
        for r in data["records"]:
            assert {"date", "host", "command", "figures"} <= set(r), f
