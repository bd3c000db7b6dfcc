"""Pages generated at build time, so that the documentation cannot disagree with the code.

At ``builder-inited`` this extension writes, under ``docs/_generated/`` (not committed):

* ``keys.md`` -- every case key, from the schema (what ``gsi check --keys`` prints);
* ``validation.md`` -- the table of ``tests/validation/results.json``, written by the
  test run's ``record_validation`` fixture (tests/conftest.py); a note when it is missing;
* ``performance.md`` -- the tables of ``benchmarks/results/*.json``;
* ``reliability.md`` -- the bad-input corpus (``tests/reliability/cases``) counted by
  expected outcome;
* ``gallery/*.md`` -- each demo of ``demos/``: a literate script (``demos/<name>.py``,
  comments in Markdown, dolfinx style) becomes prose and code cells, followed by its TOML
  twin; a TOML-only demo shows its file; both with the committed picture
  (``demos/images/<name>.png``) and, when ``make gallery`` has run the demo's ``--quick``
  form into ``docs/_build/gallery/<name>/``, its monitor plot and summary;
* ``_mathjax/mathjax`` -- the part of Debian's MathJax 2.7 the pages use.
"""
from __future__ import annotations

import datetime
import json
import pathlib
import re
import shutil

DOCS = pathlib.Path(__file__).resolve().parents[1]
ROOT = DOCS.parent
GEN = DOCS / "_generated"
GALLERY_RUNS = DOCS / "_build" / "gallery"

#: the demos of the gallery, in order: (name, one-line title)
DEMOS = [
    ("hopper_membrane", "Hopper discharging onto a membrane"),
    ("pour", "Pour: glass beads settle into a box"),
    ("thermal_silo", "Thermal silo"),
    ("drum_extrapolation", "Long-time heat extrapolation in a drum"),
    ("kiln", "Heated kiln wall"),
    ("drum", "Drum from an STL file"),
    ("belt_hopper", "Funnel onto a belt from a user .geo file"),
    ("two_structures", "Two structures on one DEM"),
    ("thermal_silo_radiation", "Thermal silo with radiation"),
    ("thermal_silo_friction", "Thermal silo with frictional heating"),
    ("plate_on_block", "Plate on a block: FE-FE contact heat"),
]


def _write(path: pathlib.Path, text: str) -> None:
    """Write only when changed (Sphinx then rebuilds only what changed)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def _copy(src: pathlib.Path, dst: pathlib.Path) -> None:
    dst.parent.mkdir(parents=True, exist_ok=True)
    if not dst.exists() or dst.read_bytes() != src.read_bytes():
        shutil.copyfile(src, dst)


# ---------------------------------------------------------------- keys
def keys_page() -> str:
    from gsi.case import Case
    from gsi.config.schema import describe
    out = ["Every key of a case file with its unit, default and meaning, generated from the "
           "schema (`gsi.config.schema.describe`) when the documentation is built: the same "
           "list `gsi check --keys` prints. `(required)` marks keys without a default; "
           "`walls[].kind` is a key of every `[[walls]]` table, `materials.NAME.E` of every "
           "`[materials.NAME]` table.", ""]
    blocks: list[tuple[str, list[str]]] = []
    for line in describe(Case):
        top = re.split(r"[.\[ ]", line, maxsplit=1)[0]
        if not blocks or blocks[-1][0] != top:
            blocks.append((top, []))
        blocks[-1][1].append(line)
    for name, block in blocks:
        out += [f"## `{name}`", "", "```text", *block, "```", ""]
    return "\n".join(out)


# ---------------------------------------------------------------- validation
def _fmt(x) -> str:
    if isinstance(x, list):
        return ", ".join(_fmt(v) for v in x)
    if isinstance(x, float):
        return f"{x:.6g}"
    return str(x)


def _deviation(r) -> str:
    ref, meas, kind = r.get("reference"), r.get("measured"), r.get("kind", "rel")
    if not isinstance(ref, (int, float)) or not isinstance(meas, (int, float)):
        return ""
    if kind == "rel" and ref != 0:
        return f"{(meas - ref) / abs(ref):+.2e} (rel.)"
    if kind in ("rel", "abs"):
        return f"{meas - ref:+.2e}"
    return ""


def _cell(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def validation_page() -> str:
    path = ROOT / "tests" / "validation" / "results.json"
    out = ["Each row is one quantity a test under `tests/` checks against an analytic, exact or "
           "published reference. The rows are not typed by hand: the test calls the "
           "`record_validation` fixture (`tests/conftest.py`) with the numbers its assert "
           "compares, the test run writes them to `tests/validation/results.json`, and this "
           "page is rendered from that file when the documentation is built (`make test` "
           "runs the tests, then `make docs`). The physics and the references are described "
           "in [the design notes](design.md).", "",
           "Tolerance kinds: *rel* holds |measured − reference| ≤ tolerance × |reference|, "
           "*abs* holds |measured − reference| ≤ tolerance; *bound*: the inequality the "
           "note states. A chaotic case is judged on an ensemble of realisations "
           "(mean ± standard error over the members, `tests/validation/conftest.py`). "
           "*goal*: a paper's own figure where the test cannot assert it at its size "
           "(shown, not asserted).", ""]
    if not path.exists():
        out += ["```{warning}",
                "No results file: `tests/validation/results.json` is written by a test run "
                "(`make test`, or `pytest tests/validation`). This build has none, so this page "
                "lists no results.", "```", ""]
        return "\n".join(out)
    records = json.loads(path.read_text()).get("records", [])
    dates = sorted({r.get("date", "") for r in records})
    hosts = sorted({r.get("host", "") for r in records})
    commits = sorted({r.get("commit", "") for r in records if r.get("commit")})
    n_fail = sum(r.get("outcome") not in (None, "passed") for r in records)
    out += [f"{len(records)} recorded checks from test runs between {dates[0]} and "
            f"{dates[-1]} (UTC) on {'; '.join(hosts)}; commit(s) {', '.join(commits) or '?'}; "
            f"{n_fail} failed.", ""]
    by_file: dict[str, list] = {}
    for r in records:
        by_file.setdefault(r["test"].split("::")[0], []).append(r)
    for f in sorted(by_file):
        out += [f"## `{f}`", "",
                "| quantity | reference | measured | deviation | tolerance | goal | outcome | "
                "source |",
                "|---|---|---|---|---|---|---|---|"]
        for r in by_file[f]:
            unit = f" {r['unit']}" if r.get("unit") else ""
            out.append("| " + " | ".join(_cell(c) for c in (
                r["name"], _fmt(r["reference"]) + unit, _fmt(r["measured"]) + unit,
                _deviation(r), f"{_fmt(r['tolerance'])} ({r.get('kind', 'rel')})",
                r.get("goal", ""), r.get("outcome", "not run to the end"),
                r.get("source", ""))) + " |")
        out.append("")
    return "\n".join(out)


# ---------------------------------------------------------------- performance
def performance_page() -> str:
    first = ["settle", "settle_scale", "fe_scale", "coupled_large", "make_test", "engine_compile"]
    files = sorted((ROOT / "benchmarks" / "results").glob("*.json"),
                   key=lambda f: (first.index(f.stem) if f.stem in first else len(first), f.stem))
    out = ["Measured figures of the benchmarks under `benchmarks/`, rendered from the "
           "machine-readable records in `benchmarks/results/*.json` (one file per benchmark; "
           "each record: date, host, command, figures, notes). Wall times depend on the "
           "host and on what else ran on it: compare rows of one host, and prefer ratios "
           "measured in one command (the settle benchmark runs gsi and LIGGGHTS back to "
           "back).", ""]
    if not files:
        return "\n".join(out + ["No records in `benchmarks/results/`.", ""])
    for f in files:
        data = json.loads(f.read_text())
        out += [f"## {data.get('title', f.stem)}", "", data.get("what", ""), "",
                f"Script: `{data.get('script', '')}`; records: `benchmarks/results/{f.name}`.", ""]
        for r in sorted(data.get("records", []), key=lambda r: r.get("date", ""), reverse=True):
            figs = r.get("figures", {})
            fig = "; ".join(f"{k} = {_fmt(v)}" for k, v in figs.items())
            out += [f"**{r.get('date', '?')}** — {r.get('host', '')}", "",
                    f"```text\n{r.get('command', '')}\n```", ""]
            if fig:
                out += [f"Figures: {fig}", ""]
            if r.get("notes"):
                out += [r["notes"], ""]
        if data.get("readme_text"):
            out += ["<details><summary>The former README's text on this benchmark "
                    "(verbatim)</summary>", "", "````text", data["readme_text"], "````", "",
                    "</details>", ""]
    return "\n".join(out)


# ---------------------------------------------------------------- gallery
def literate_to_markdown(source: str) -> str:
    """A dolfinx-style literate script as MyST Markdown: runs of ``# `` comment lines
    become prose, everything else ```python blocks (blank edges trimmed)."""
    out, code, prose = [], [], []

    def flush_code():
        while code and not code[0].strip():
            code.pop(0)
        while code and not code[-1].strip():
            code.pop()
        if code:
            out.extend(["```python", *code, "```", ""])
        code.clear()

    def flush_prose():
        if prose:
            out.extend([*prose, ""])
        prose.clear()

    for line in source.splitlines():
        if line == "#" or line.startswith("# ") and not line.startswith("# noqa"):
            if code and any(c.strip() for c in code):
                flush_code()
            code.clear()
            prose.append(line[2:] if line.startswith("# ") else "")
        else:
            if prose:
                flush_prose()
            code.append(line)
    flush_prose()
    flush_code()
    return "\n".join(out)


def _demo_page(name: str, title: str) -> str:
    script, toml = ROOT / "demos" / f"{name}.py", ROOT / "demos" / f"{name}.toml"
    gdir = GEN / "gallery"
    lines = []
    if script.exists():
        text = literate_to_markdown(script.read_text())
        # the script's first heading is the page title
        lines.append(text)
    else:
        head = [l[2:] for l in toml.read_text().splitlines() if l.startswith("# ")]
        lines += [f"# {title}", "", *(head or []), ""]
    pic = ROOT / "demos" / "images" / f"{name}.png"
    if not pic.exists() and name == "thermal_silo_radiation":
        pic = ROOT / "demos" / "images" / "thermal_silo_radiation_share.png"
    lines += ["## Pictures", ""]
    if pic.exists():
        _copy(pic, gdir / "images" / pic.name)
        lines += [f"```{{figure}} images/{pic.name}", ":width: 100%", "",
                  "The full run (committed picture, `demos/images/`).", "```", ""]
    run = GALLERY_RUNS / name
    if (run / "monitors.png").exists():
        _copy(run / "monitors.png", gdir / "images" / f"{name}_quick_monitors.png")
        lines += [f"```{{figure}} images/{name}_quick_monitors.png", ":width: 90%", "",
                  f"Monitors of `gsi run demos/{name}.toml --quick`, run when the "
                  "documentation was built (`make gallery`).", "```", ""]
    if (run / f"{name}.png").exists():
        _copy(run / f"{name}.png", gdir / "images" / f"{name}_quick.png")
        lines += [f"```{{figure}} images/{name}_quick.png", ":width: 90%", "",
                  "The last snapshot of the `--quick` run.", "```", ""]
    if (run / "summary.txt").exists():
        lines += ["The `--quick` run's summary:", "", "```text",
                  (run / "summary.txt").read_text().strip(), "```", ""]
    elif not pic.exists():
        lines += ["No picture: run `make gallery` to run the demo's `--quick` form.", ""]
    if toml.exists():
        lines += ["## The case file", "",
                  f"`demos/{name}.toml` (`gsi run demos/{name}.toml [--quick] --out DIR`):", "",
                  "```toml", toml.read_text().rstrip(), "```", ""]
    return "\n".join(lines)


def gallery_pages() -> dict[str, str]:
    pages = {}
    for name, title in DEMOS:
        if (ROOT / "demos" / f"{name}.toml").exists() or (ROOT / "demos" / f"{name}.py").exists():
            pages[f"gallery/{name}.md"] = _demo_page(name, title)
    ran = sorted(p.name for p in GALLERY_RUNS.glob("*") if (p / "summary.txt").exists())
    idx = [
           "Each demo is a case under `demos/`: `gsi run demos/<name>.toml [--quick] --out DIR`. "
           "The literate ones are also Python scripts in the style of the dolfinx demos "
           "(`python demos/<name>.py [--quick] [--out DIR]`), read top to bottom: what the demo "
           "shows, the equations, then short steps of prose and code over the public "
           "`gsi.case` API. `--quick` finishes in under two minutes and is what the tests run "
           "(`tests/demos/`).", "",
           "The pictures of the full runs are committed (`demos/images/`). `make gallery` runs "
           "every demo's `--quick` form into `docs/_build/gallery/` (up to two minutes each on "
           "two cores) and the next `make docs` shows their monitor plots and summaries "
           "beside the source; `make docs` alone does not run the demos, so that it stays fast "
           "enough for every CI run. The literate scripts are rendered by a small converter "
           "(`docs/_ext/gsi_docs.py`: comment lines become prose, the rest code cells) rather "
           "than by sphinx-gallery, whose Debian 12 version (0.10) expects its own "
           "`plot_*.py` cell format. " +
           (f"This build includes the quick runs of: {', '.join(ran)}." if ran else
            "This build includes no quick runs."), "",
           "```{toctree}", ":maxdepth: 1", "", *[f"_generated/{p[:-3]}" for p in pages], "```", ""]
    pages["gallery_index.md"] = "\n".join(idx)
    return pages


# ---------------------------------------------------------------- mathjax
MATHJAX = pathlib.Path("/usr/share/javascript/mathjax")
MATHJAX_PARTS = ["MathJax.js", "config/TeX-AMS_CHTML.js", "jax/input/TeX", "jax/output/CommonHTML",
                 "jax/element", "extensions", "fonts/HTML-CSS/TeX/woff"]


def copy_mathjax() -> None:
    if not (MATHJAX / "MathJax.js").exists():
        return
    dst = GEN / "_mathjax" / "mathjax"
    for part in MATHJAX_PARTS:
        src = MATHJAX / part
        if src.is_dir():
            for f in src.rglob("*"):
                if f.is_file():
                    _copy(f, dst / part / f.relative_to(src))
        elif src.exists():
            _copy(src, dst / part)


# ---------------------------------------------------------------- reliability
#: outcome of a corpus case (its header's ``via``) -> the words of the table
OUTCOMES = {"check": "refused by `gsi check`, one line naming the key",
            "run": "refused by `gsi run` at set-up, one line naming the key",
            "warn": "accepted with one warning line naming the key",
            "ok": "valid input, accepted silently"}


def corpus_counts(cases: pathlib.Path = ROOT / "tests" / "reliability" / "cases") -> dict:
    """{outcome: number of cases} of the bad-input corpus, from each file's first line
    ``# expect: KEY | via: OUTCOME | what``."""
    counts = {k: 0 for k in OUTCOMES}
    for path in sorted(cases.glob("*.toml")):
        first = path.read_bytes().split(b"\n", 1)[0].decode("utf-8", "replace").lstrip("\ufeff")
        via = first.split(" | ")[1].removeprefix("via: ").strip()
        counts[via] = counts.get(via, 0) + 1
    return counts


def reliability_page() -> str:
    counts = corpus_counts()
    rows = [f"| {OUTCOMES.get(k, k)} | {n} |" for k, n in counts.items()]
    return "\n".join(["| expected outcome | cases |", "|---|---|", *rows,
                      f"| **total** | **{sum(counts.values())}** |", ""])


def generate(app=None) -> None:
    GEN.mkdir(exist_ok=True)
    _write(GEN / "keys.md", keys_page())
    _write(GEN / "reliability.md", reliability_page())
    _write(GEN / "validation.md", validation_page())
    _write(GEN / "performance.md", performance_page())
    for rel, text in gallery_pages().items():
        _write(GEN / rel, text)
    copy_mathjax()


_LITERAL = re.compile(r"(``.*?``)")


def escape_bars(app, what, name, obj, options, lines) -> None:
    """Docstrings write absolute values as |x|, which reStructuredText reads as a
    substitution: escape a bar outside literals, except in table rows."""
    if lines and lines[-1].strip():
        lines.append("")           # a field list must end with a blank line
    for i, line in enumerate(lines):
        if "|" not in line or line.lstrip().startswith(("|", "+")):
            continue
        parts = _LITERAL.split(line)
        lines[i] = "".join(p if p.startswith("``") else p.replace("|", "\\|") for p in parts)


def fix_furo_css(app, exception) -> None:
    """Debian's furo (dfsg) imports normalize.css from /javascript/ (where Debian's web
    server would serve libjs-normalize.css): copy it into the site and import it from
    there, so the site works wherever it is served."""
    if exception is not None or app.builder.format != "html":
        return
    css = pathlib.Path(app.outdir) / "_static" / "styles" / "furo.css"
    src = pathlib.Path("/usr/share/javascript/normalize.css/normalize.css")
    if not css.exists() or "/javascript/normalize.css/" not in css.read_text():
        return
    if src.exists():
        _copy(src, css.parent / "normalize.css")
        css.write_text(css.read_text().replace("url(/javascript/normalize.css/normalize.css)",
                                               "url(normalize.css)"))


def setup(app):
    generate()            # before Sphinx lists the source files
    app.connect("build-finished", fix_furo_css)
    app.connect("autodoc-process-docstring", escape_bars)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
