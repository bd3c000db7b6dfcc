"""The architecture of gsi, read from its source with ``ast`` (nothing is imported):

* no import cycle between gsi modules (module-level and function-level imports alike);
* no upward import: each package sits on a layer (:data:`LAYERS`) and imports only its
  own layer or lower ones; ``gsi.dem`` and ``gsi.fem`` never import each other;
* no file in gsi/ over :data:`MAX_FILE_LINES` lines, no class over :data:`MAX_CLASS_LINES`
  (the DEM engine's files, owned by the engine work, are exempt: :data:`ENGINE_OWNED`);
* no object reaches into another one's private fields, in gsi/, tests/ and demos/
  (:func:`private_access`).

Run as a script it prints the two figures of issue 29 for any checkout::

    python tests/unit/test_architecture.py [--root DIR]

1. the largest file in gsi/ (lines);
2. the files a reader passes through from a wall contact force to the FE nodal load and
   back (:func:`coupling_path`): one coupling interval followed through the code, hop by
   hop, each hop named by the class or function that carries the data (:data:`ROUND_TRIP`)
   and located in the module that defines it (by ``ast``, so the figure follows the
   code when it moves). The figures are the distinct files on that trip and the times it
   crosses between packages (dem, coupling, fem, run).
"""
from __future__ import annotations

import ast
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]

MAX_FILE_LINES = 500
MAX_CLASS_LINES = 300

#: files exempt from the size limits: none (the engine split into pair_lanes/wall_lanes)
ENGINE_OWNED = set()

#: layers, lowest first: a module may import its own layer and lower ones only.
#: Keys are module prefixes (the longest matching prefix decides).
LAYERS = {
    "gsi": 0, "gsi.errors": 0, "gsi.jit": 0, "gsi.config": 0, "gsi.checkpoint": 0,
    "gsi.viz": 0,
    "gsi.dem": 1, "gsi.fem": 1,
    "gsi.meshes": 2, "gsi.post": 2,
    "gsi.coupling": 3,
    "gsi.case": 4,
    "gsi.extrapolation": 5, "gsi.studies": 5,
    "gsi.run": 6, "gsi.cli": 6,
}

#: packages of one layer that must not import each other
SIBLINGS_APART = [("gsi.dem", "gsi.fem")]

#: one coupling interval, force -> nodal load -> FE step -> deformed wall -> DEM, as the
#: hops a reader follows: (defining name, what happens there). Every hop the data takes is
#: listed (ContactSurface, which scatters the loads to their owning ranks and gathers the
#: displacements, was missing before 2026-12-04: the trip then counted 9 files, 10 with
#: it). The trip ends where the wall writes its new vertices into the mesh bundle that
#: the engine reads: the wall no longer calls back into the simulation (the step loop asks
#: whether a wall moved half the skin, as it does for particles).
ROUND_TRIP = [
    ("Runner", "the loop ends the structure's interval (finish_structures)"),
    ("CoupledStructure", "the structure finishes its interval (finish)"),
    ("StaggeredCoupling", "the interval: the wall's impulse over it becomes a load"),
    ("MeshWall", "the wall's vertex_impulse, summed by the engine ..."),
    ("mesh_scatter", "... from each contact force and its vertex weights"),
    ("SurfaceInterface", "wall vertices -> FE surface nodes (add_nodal_loads)"),
    ("ContactSurface", "the loads to the ranks owning the vertices"),
    ("NodalLoads", "the FE nodal-load assembly"),
    ("Elasticity", "the FE step"),
    ("SurfaceInterface", "FE displacement and velocity -> wall vertices"),
    ("ContactSurface", "gathered from the owning ranks"),
    ("StaggeredCoupling", "the wall follows the FE (set_vertices)"),
    ("MeshWall", "set_vertices: the mesh bundle the engine reads at the next step"),
]

# ---------------------------------------------------------------------- reading the source
def modules(root: pathlib.Path = ROOT) -> dict[str, pathlib.Path]:
    """gsi module name -> file."""
    out = {}
    for path in sorted((root / "gsi").rglob("*.py")):
        rel = path.relative_to(root).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def imports(root: pathlib.Path = ROOT) -> dict[str, set[str]]:
    """gsi module -> the gsi modules it imports (anywhere in the file)."""
    mods = modules(root)
    graph = {}
    for name, path in mods.items():
        tree = ast.parse(path.read_text(), str(path))
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        deps = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    up = package.split(".")
                    up = up[:len(up) - node.level + 1]
                    base = ".".join(up + ([base] if base else []))
                targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in mods else base
                           for a in node.names]
            else:
                continue
            for t in targets:
                while t and t not in mods:
                    t = t.rpartition(".")[0]
                if t and t != name and t.startswith("gsi"):
                    deps.add(t)
        graph[name] = deps
    return graph


def layer(module: str) -> int:
    key = max((k for k in LAYERS if module == k or module.startswith(k + ".")), key=len)
    return LAYERS[key]


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in graph:
        if v not in index:
            visit(v)
    return out


def file_lines(root: pathlib.Path = ROOT) -> dict[str, int]:
    """gsi file (relative path) -> lines."""
    return {str(p.relative_to(root)): len(p.read_text().splitlines())
            for p in sorted((root / "gsi").rglob("*.py"))}


def class_lines(root: pathlib.Path = ROOT) -> dict[str, int]:
    """``file:Class`` -> lines of the class statement (decorators excluded)."""
    out = {}
    for p in sorted((root / "gsi").rglob("*.py")):
        for node in ast.walk(ast.parse(p.read_text())):
            if isinstance(node, ast.ClassDef):
                out[f"{p.relative_to(root)}:{node.name}"] = node.end_lineno - node.lineno + 1
    return out


def defining(name: str, root: pathlib.Path = ROOT) -> str:
    """The gsi module that defines the top-level function or class ``name``."""
    found = [m for m, p in modules(root).items()
             if any(isinstance(n, (ast.FunctionDef, ast.ClassDef)) and n.name == name
                    for n in ast.parse(p.read_text()).body)]
    assert len(found) == 1, (name, found)
    return found[0]


def coupling_path(root: pathlib.Path = ROOT) -> list[str]:
    """The modules of :data:`ROUND_TRIP`, hop by hop."""
    return [defining(name, root) for name, _ in ROUND_TRIP]


def _package(module: str) -> str:
    return ".".join(module.split(".")[:2])


def figures(root: pathlib.Path = ROOT) -> dict:
    lines = file_lines(root)
    biggest = max(lines, key=lines.get)
    trip = coupling_path(root)
    crossings = sum(_package(a) != _package(b) for a, b in zip(trip, trip[1:]))
    return dict(largest_file=biggest, largest_file_lines=lines[biggest], trip=trip,
                round_trip_files=len(set(trip)), crossings=crossings)


# ---------------------------------------------------------------------- the tests
def test_no_import_cycles():
    assert cycles(imports()) == []


def test_no_upward_imports():
    bad = [f"{m} (layer {layer(m)}) imports {d} (layer {layer(d)})"
           for m, deps in imports().items() for d in sorted(deps) if layer(d) > layer(m)]
    assert bad == []


def test_dem_and_fem_never_import_each_other():
    bad = [f"{m} imports {d}" for m, deps in imports().items() for d in deps
           for a, b in SIBLINGS_APART for x, y in ((a, b), (b, a))
           if (m == x or m.startswith(x + ".")) and (d == y or d.startswith(y + "."))]
    assert bad == []


def test_no_file_over_the_limit():
    bad = {f: n for f, n in file_lines().items()
           if n > MAX_FILE_LINES and f not in ENGINE_OWNED}
    assert bad == {}


def test_no_class_over_the_limit():
    bad = {c: n for c, n in class_lines().items()
           if n > MAX_CLASS_LINES and c.partition(":")[0] not in ENGINE_OWNED}
    assert bad == {}


#: module names found in more than one package, each naming one concept at two layers (the
#: case table and the object it builds, the mesh and the study of a drum, the DEM's and the
#: FE's writers); any other repeated name is two different things under one name
SHARED_NAMES = {"cli.py", "output.py", "materials.py", "walls.py", "drum.py"}


def test_no_two_modules_share_a_name_for_different_things():
    seen = {}
    for f in (ROOT / "gsi").rglob("*.py"):
        if f.name != "__init__.py":
            seen.setdefault(f.name, []).append(f.relative_to(ROOT).as_posix())
    repeated = {n: sorted(p) for n, p in seen.items() if len(p) > 1 and n not in SHARED_NAMES}
    assert repeated == {}


#: private names of other objects that are public by their own library's convention:
#: namedtuple's API (_fields, _replace, _asdict, _make), os._exit, argparse's _actions
#: (argparse has no public way to list a parser's options)
FOREIGN_PRIVATE = {"_fields", "_replace", "_asdict", "_make", "_exit", "_actions"}

#: the one module allowed to reach into dolfinx's objects (calls that differ by version)
COMPAT = "gsi/fem/compat.py"


def private_access(root: pathlib.Path = ROOT, folders=("gsi", "tests", "demos")) -> list:
    """Every ``x._name`` where ``x`` is not ``self``, ``cls`` or ``super()``, and every
    ``from gsi... import _name``, in the given folders: one object reaching into another's
    private fields (issue 29: collaborators talk through public methods, tests and demos
    use the public API)."""
    hits = []
    for folder in folders:
        for f in sorted((root / folder).rglob("*.py")):
            rel = f.relative_to(root).as_posix()
            if rel == COMPAT:
                continue
            for node in ast.walk(ast.parse(f.read_text())):
                if isinstance(node, ast.Attribute) and _is_private(node.attr):
                    v = node.value
                    own = (isinstance(v, ast.Name) and v.id in ("self", "cls")) or (
                        isinstance(v, ast.Call) and isinstance(v.func, ast.Name)
                        and v.func.id == "super")
                    if not own and node.attr not in FOREIGN_PRIVATE:
                        hits.append(f"{rel}:{node.lineno}: {ast.unparse(node)}")
                elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("gsi"):
                    hits += [f"{rel}:{node.lineno}: from {node.module} import {a.name}"
                             for a in node.names if _is_private(a.name)]
    return hits


def _is_private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def test_no_object_reaches_into_another_ones_private_fields():
    assert private_access() == []


def test_the_private_access_scan_finds_what_it_looks_for(tmp_path):
    (tmp_path / "gsi").mkdir()
    (tmp_path / "gsi" / "a.py").write_text(
        "from gsi.b import _helper\n"
        "class A:\n    def f(self, sim):\n        self._ok = super()._g()\n"
        "        return sim._rebuild(), P._fields\n")
    for d in ("tests", "demos"):
        (tmp_path / d).mkdir()
    assert private_access(tmp_path) == ["gsi/a.py:1: from gsi.b import _helper",
                                        "gsi/a.py:5: sim._rebuild"]


def test_the_figures_are_computed():
    f = figures()
    assert len(f["trip"]) == len(ROUND_TRIP) and f["round_trip_files"] >= 4
    print(f"\nlargest file {f['largest_file']} ({f['largest_file_lines']} lines); "
          f"force -> load -> back: {f['round_trip_files']} files, "
          f"{f['crossings']} package crossings")


if __name__ == "__main__":
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--root", default=str(ROOT), help="a gsi checkout (default: this one)")
    root = pathlib.Path(ap.parse_args().root).resolve()
    f = figures(root)
    lines = file_lines(root)
    print(f"root: {root}")
    print(f"largest file: {f['largest_file']} ({f['largest_file_lines']} lines); "
          f"largest outside the engine-owned files: "
          f"{max((n, p) for p, n in lines.items() if p not in ENGINE_OWNED)}")
    for (name, what), m in zip(ROUND_TRIP, f["trip"]):
        print(f"  {name:<18} {m:<28} {what}")
    print(f"force -> nodal load -> back: {f['round_trip_files']} distinct files, "
          f"{f['crossings']} package crossings")
    print(f"import cycles: {cycles(imports(root))}")
    up = [(m, d) for m, deps in imports(root).items() for d in deps if layer(d) > layer(m)]
    print(f"upward imports: {len(up)} {sorted(up)[:8]}")
    print(f"files over {MAX_FILE_LINES} lines: "
          f"{sorted((n, p) for p, n in lines.items() if n > MAX_FILE_LINES)}")
    print(f"classes over {MAX_CLASS_LINES} lines: "
          f"{sorted((n, c) for c, n in class_lines(root).items() if n > MAX_CLASS_LINES)}")
