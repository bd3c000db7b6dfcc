"""Material library and input checking."""
import pytest

from gsi.errors import GsiInputError
from gsi.fem.materials import MATERIALS, StructuralMaterial, get_material


def test_library_has_the_four_materials_with_sane_values():
    assert set(MATERIALS) >= {"steel", "aluminium", "rubber", "concrete"}
    steel = MATERIALS["steel"]
    assert steel.E == 210e9 and steel.nu == 0.3 and steel.rho == 7850.0
    # Lame parameters from E, nu
    assert steel.mu == pytest.approx(210e9 / 2.6)
    assert steel.lmbda == pytest.approx(210e9 * 0.3 / (1.3 * 0.4))
    # ordering a reviewer expects: rubber softest, aluminium conducts best
    assert min(MATERIALS.values(), key=lambda m: m.E) is MATERIALS["rubber"]
    assert max(MATERIALS.values(), key=lambda m: m.k) is MATERIALS["aluminium"]


def test_get_material_from_name_table_and_base():
    assert get_material("concrete") is MATERIALS["concrete"]
    m = get_material({"base": "steel", "E": 200e9})
    assert m.E == 200e9 and m.rho == 7850.0
    m = get_material({"E": 1e9, "nu": 0.25, "rho": 1000.0})
    assert m.alpha == 0.0


@pytest.mark.parametrize("spec, key", [
    ("unobtainium", "structure.material"),
    ({"base": "steel", "Young": 1.0}, "Young"),
    ({"E": 1e9, "rho": 1.0}, "nu"),
    ({"base": "steel", "nu": 0.5}, "nu"),
    ({"base": "steel", "E": -1.0}, "E"),
])
def test_bad_materials_raise_one_line_errors(spec, key):
    with pytest.raises(GsiInputError) as err:
        get_material(spec)
    assert key in str(err.value) and "\n" not in str(err.value)


def test_direct_construction_is_checked():
    with pytest.raises(GsiInputError):
        StructuralMaterial(E=1e9, nu=0.3, rho=0.0)
