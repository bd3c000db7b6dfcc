"""A structure from the user's own gmsh file: a ``.geo`` script or a ``.msh`` mesh.

The file must define physical groups: at least one volume (its tetrahedra are the
structure) and the surfaces the case refers to (supports, loads, contact, thermal
conditions). Their names are the file's own; a case maps gsi's names onto them
(``structures.tags``, see :func:`gsi.case.structure.Structure`).

* ``.msh``: read as it is (first-order tetrahedra: the coupling needs straight-sided
  elements).
* ``.geo``: gmsh runs the script and meshes it in 3D. ``params`` override the script's
  ``DefineConstant[...]`` values before it runs: a key matches a constant's ONELAB name
  (``"Parameters/length"``) or its last part (``"length"``); gmsh's API sets them with
  ``gmsh.onelab.setNumber`` (gmsh 4.8 has no ``gmsh.parser``; the ``-setnumber`` command
  line option would outlive the session). The ONELAB database also outlives
  ``gmsh.finalize``, so it is cleared before every read.

Global vertex ids are the gmsh node tags minus one, as for the shipped builders.
"""
from __future__ import annotations

import pathlib

from mpi4py import MPI

from gsi.errors import GsiInputError

from ._common import StructureMesh

__all__ = ["load", "physical_groups"]

SUFFIXES = (".geo", ".msh")
_SYSTEM = ("Gmsh/", "ONELAB/")


def check_readable(path: pathlib.Path, key: str) -> None:
    """Refuse a file gmsh would misparse *and be harmed by*: gmsh 4.8 reads a file that is
    not a mesh as a .geo script, and a binary one (random bytes) leaves its script lexer
    broken for the rest of the process -- every later .geo then fails with "line 0:
    syntax error".  A .msh must start with ``$MeshFormat``; a .geo must be text."""
    head = path.read_bytes()[:1 << 16]
    if path.suffix.lower() == ".msh":
        if not head.lstrip().startswith(b"$MeshFormat"):
            raise GsiInputError(f"{key}.file = '{path}': not a gmsh mesh (a .msh file starts "
                                "with $MeshFormat); give a gmsh .msh or .geo file")
        return
    try:
        text = head.decode("utf-8")
    except UnicodeDecodeError:
        text = None
    if text is None or any(ord(c) < 32 and c not in "\t\n\r\f" for c in text):
        raise GsiInputError(f"{key}.file = '{path}': not a gmsh script (binary content); "
                            "give a gmsh .geo text file or a .msh mesh")


def _open(gmsh, path: pathlib.Path, params: dict | None, key: str) -> dict:
    """Open ``path`` in a live gmsh session with the DefineConstant overrides ``params``.
    Returns the script's constants {onelab name: value} (empty for .msh)."""
    check_readable(path, key)
    gmsh.onelab.clear()
    gmsh.open(str(path))
    if path.suffix != ".geo":
        if params:
            raise GsiInputError(f"{key}.geometry = {{...}}: parameters apply to a .geo script "
                                f"only; {path.name} is a mesh")
        return {}
    names = [n for n in gmsh.onelab.getNames() if not n.startswith(_SYSTEM)]
    consts = {n: float(gmsh.onelab.getNumber(n)[0]) for n in names
              if len(gmsh.onelab.getNumber(n))}
    if not params:
        return consts
    by_short = {}
    for n in consts:
        by_short.setdefault(n.rsplit("/", 1)[-1], []).append(n)
    chosen = {}
    for k, v in params.items():
        full = [k] if k in consts else by_short.get(k, [])
        if len(full) != 1:
            known = sorted(n.rsplit("/", 1)[-1] for n in consts)
            why = "ambiguous" if full else "not a DefineConstant of the script"
            raise GsiInputError(f"{key}.geometry.{k} = {v!r}: {why} in {path.name}; "
                                f"its constants: {', '.join(known) or 'none'}")
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise GsiInputError(f"{key}.geometry.{k} = {v!r}: must be a number")
        chosen[full[0]] = float(v)
    gmsh.clear()
    gmsh.onelab.clear()
    for n, v in chosen.items():
        gmsh.onelab.setNumber(n, [v])
    gmsh.open(str(path))
    consts.update(chosen)
    return consts


def _read(gmsh, path: pathlib.Path, params: dict | None, key: str) -> dict:
    """:func:`_open` with gmsh's failures (plain Exceptions, undecodable messages about a
    binary file, anything else) as one ``error:`` line naming the key and the file."""
    from gsi.readers import ReadFailed, guarded
    try:
        return guarded(_open, gmsh, path, params, key, keep=(GsiInputError,))
    except ReadFailed as exc:
        raise GsiInputError(f"{key}.file = '{path}': gmsh cannot read it ({exc})") from None


def _groups(gmsh) -> tuple[dict, dict]:
    """(surface groups, volume groups) of the model: {name: physical number}; an unnamed
    group is named by its number."""
    surfaces, volumes = {}, {}
    for dim, tag in gmsh.model.getPhysicalGroups():
        name = gmsh.model.getPhysicalName(dim, tag) or str(tag)
        if dim == 2:
            surfaces[name] = int(tag)
        elif dim == 3:
            volumes[name] = int(tag)
    return surfaces, volumes


def _session():
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    return gmsh


def _check_path(path, key: str) -> pathlib.Path:
    path = pathlib.Path(path)
    if path.suffix.lower() not in SUFFIXES:
        raise GsiInputError(f"{key}.file = '{path}': must be a gmsh .geo or .msh file")
    if not path.is_file():
        raise GsiInputError(f"{key}.file = '{path}': no such file")
    return path


def physical_groups(path, *, params: dict | None = None, key: str = "structure") -> dict:
    """Read the physical groups of a gmsh file without meshing (one process, cheap).

    Returns ``dict(surfaces={name: number}, volumes={name: number}, constants={name:
    value})``. Raises a one-line GsiInputError for an unreadable file or bad ``params``.
    """
    path = _check_path(path, key)
    gmsh = _session()
    try:
        consts = _read(gmsh, path, params, key)
        surfaces, volumes = _groups(gmsh)
    finally:
        gmsh.finalize()
    return dict(surfaces=surfaces, volumes=volumes, constants=consts)


def load(path, *, params: dict | None = None, comm: MPI.Comm = MPI.COMM_WORLD, root: int = 0,
         key: str = "structure") -> StructureMesh:
    """Build the distributed structure of a gmsh ``.geo``/``.msh`` file (collective).

    Parameters
    ----------
    path : str or Path
        The file (read on rank ``root``).
    params : dict, optional
        ``.geo`` only: DefineConstant overrides {name: number} (see the module docstring).
    comm, root : MPI communicator and the rank that runs gmsh.
    key : str
        Case key path used in error messages (e.g. "structures[0]").

    Returns
    -------
    StructureMesh
        ``tags``: the surface groups by name and "volume" (the first volume group);
        ``volumes``: every volume group by name; ``params``: the file and the script's
        constants.
    """
    msg = result = None
    gmsh = None
    if comm.rank == root:
        try:
            p = _check_path(path, key)
            gmsh = _session()
            consts = _read(gmsh, p, params, key)
            surfaces, volumes = _groups(gmsh)
            if not volumes:
                raise GsiInputError(f"{key}.file = '{p.name}': no physical volume; add a "
                                    "'Physical Volume(\"name\") = {...};' (its tetrahedra are "
                                    "the structure)")
            if p.suffix == ".geo":
                from gsi.readers import ReadFailed, guarded
                try:
                    guarded(gmsh.model.mesh.generate, 3)
                except ReadFailed as exc:
                    raise GsiInputError(f"{key}.file = '{p}': gmsh cannot mesh it "
                                        f"({exc})") from None
            types = set(int(t) for t in gmsh.model.mesh.getElementTypes(3))
            if types != {4}:
                raise GsiInputError(f"{key}.file = '{p.name}': the volume mesh must be "
                                    "first-order tetrahedra only (gmsh element type 4; set "
                                    "Mesh.ElementOrder = 1)")
            tags = dict(surfaces)
            tags["volume"] = next(iter(volumes.values()))
            result = (tags, volumes, dict(file=str(p), **consts))
        except GsiInputError as exc:
            msg = str(exc)
            if gmsh is not None:
                gmsh.finalize()
                gmsh = None
    msg = comm.bcast(msg, root=root)
    if msg is not None:
        raise GsiInputError(msg)
    from gsi.fem import compat
    try:
        tags, volumes, info = comm.bcast(result, root=root)
        mesh, ct, ft = compat.model_to_mesh(gmsh.model if gmsh is not None else None, comm,
                                            root, gdim=3)
    finally:
        if gmsh is not None:
            gmsh.finalize()
    return StructureMesh(mesh=mesh, cell_tags=ct, facet_tags=ft, tags=tags, params=info,
                         volumes=volumes)
