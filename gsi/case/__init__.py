"""The case model: a study composed of parts, each a TOML table and a Python object.

See :mod:`gsi.case.case` for the list of tables; ``gsi check --keys`` lists every key.
"""
from gsi.case.case import Case, case_from_table, case_to_table, load_case, merge_tables
from gsi.case.materials import Material, Pair
from gsi.case.monitors import Monitor
from gsi.case.regions import Region
from gsi.case.settings import CaseInfo, Dem, Output, Run
from gsi.case.sources import ParticleSource, Size
from gsi.case.structure import Structure
from gsi.case.walls import Motion, Wall

__all__ = ["Case", "CaseInfo", "Run", "Dem", "Output", "Material", "Pair", "Region", "Size",
           "ParticleSource", "Wall", "Motion", "Structure", "Monitor", "load_case",
           "case_from_table", "case_to_table", "merge_tables"]
