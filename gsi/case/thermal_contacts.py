r"""Heat across the contact of two structures: one ``[[thermal_contacts]]`` table.

Two ``[[structures]]`` with heat (``contact.mode = "thermal"`` or ``"both"``) whose
meshes overlap slightly on the named surfaces exchange heat through the overlap with a
contact resistance R_c (the FDEM contact-heat model, :mod:`gsi.fem.contact_heat`)::

    [[thermal_contacts]]
    structures = ["plate", "block"]
    tags = ["z0", "z1"]                 # the touching surface of each, in that order
    R_c = 1.0e-3                        # m^2 K/W
    temperature = "local"               # or "mean" (the bodies' mean temperatures)

The structures of a connected set of contacts step together as one PETSc system
(:class:`gsi.fem.contact_heat.ContactHeatSystem`): they need the same ``contact.n_sub``
and ``thermal.theta``, and the run is serial. Each structure's energy record
(``<name>_energy.csv``) has the heat it received through its contacts (``Q_contact``).
"""
from __future__ import annotations

from dataclasses import dataclass

from gsi.config.schema import one_of, param, positive
from gsi.errors import GsiInputError

__all__ = ["ThermalContact", "build_contact_groups"]


@dataclass(kw_only=True)
class ThermalContact:
    """A heat contact between two structures (see the module docstring)."""

    structures: tuple[str, ...] = param(doc="the two [[structures]] names in contact")
    tags: tuple[str, ...] = param(doc="the touching surface tag of each structure, in order")
    R_c: float = param(unit="m^2 K/W", check=positive(), doc="contact resistance")
    temperature: str = param("local", check=one_of("local", "mean"),
                             doc="Delta T from the touching cells' surface nodes (local) or "
                                 "the bodies' mean temperatures (mean, explicit)")

    def validate(self, path: str) -> None:
        for k in ("structures", "tags"):
            v = getattr(self, k)
            if len(v) != 2:
                raise GsiInputError(f"{path}.{k} = {list(v)}: must name two, one per structure")
        if self.structures[0] == self.structures[1]:
            raise GsiInputError(f"{path}.structures = {list(self.structures)}: must name two "
                                "different structures")

    def check(self, path: str, *, structures: dict) -> None:
        """Both structures exist, have heat and carry the tags (``structures``: name ->
        gsi.case.Structure)."""
        for name, tag in zip(self.structures, self.tags):
            if name not in structures:
                raise GsiInputError(f"{path}.structures = {list(self.structures)}: '{name}' is "
                                    f"not a [[structures]] name; defined: "
                                    f"{', '.join(structures) or 'none'}")
            st = structures[name]
            if not st.has_heat:
                raise GsiInputError(f"{path}.structures: '{name}' has contact.mode = "
                                    f"'{st.contact.mode}'; a heat contact needs mode = "
                                    "'thermal' or 'both'")


def build_contact_groups(contacts, built: dict) -> list:
    """One :class:`gsi.fem.contact_heat.ContactHeatSystem` per connected set of contacts.

    ``contacts``: the case's ThermalContact tables; ``built``: name -> built structure
    (:class:`gsi.coupling.coupled_structure.CoupledStructure`)."""
    from gsi.fem.contact_heat import ContactHeatSystem
    from gsi.fem.contact_heat import ThermalContact as FeContact
    fe = []
    for i, c in enumerate(contacts):
        a, b = (built[n] for n in c.structures)
        fe.append((set(c.structures), FeContact(
            a.heat, b.heat, tags_a=[c.tags[0]], tags_b=[c.tags[1]], R_c=c.R_c,
            temperature=c.temperature, key=f"thermal_contacts[{i}]")))
    groups = []                                   # connected components over structure names
    for names, contact in fe:
        joined = [g for g in groups if g[0] & names]
        for g in joined:
            groups.remove(g)
        merged = (set(names).union(*(g[0] for g in joined)),
                  [contact] + [c for g in joined for c in g[1]])
        groups.append(merged)
    return [ContactHeatSystem(cs, key="thermal_contacts") for _, cs in groups]
