"""Regenerate ``cases/``: the bad-input corpus, each a demo case with one thing broken.

Run ``python tests/reliability/make_corpus.py`` after changing a demo; review the diff.
Each file's first line is ``# expect: KEY | via: check|run|warn|ok | what is broken``: the
key the one-line error (or warning) must name, and the outcome: ``check`` (refused by ``gsi
check``), ``run`` (only ``gsi run`` finds it, at set-up), ``warn`` (accepted with a warning
naming the key) or ``ok`` (a valid input, accepted silently). The second corpus (a careful
user's slips) is in ``corpus_careful.py``.
"""
from __future__ import annotations

import pathlib

HERE = pathlib.Path(__file__).parent
CASES = HERE / "cases"
DEMOS = HERE.parents[1] / "demos"


def _base(name: str) -> str:
    lines = (DEMOS / f"{name}.toml").read_text().splitlines()
    while lines and lines[0].startswith("#"):
        lines.pop(0)
    text = "\n".join(lines) + "\n"
    return (text.replace('"data/drum.stl"', '"../../../demos/data/drum.stl"')
            .replace('"../meshes/belt.geo"', '"../../../meshes/belt.geo"')
            .replace('"data/plate_particles.csv"', '"../../../demos/data/plate_particles.csv"'))


P, D, H, B, T, R = (_base(n) for n in ("pour", "drum", "hopper_membrane", "belt_hopper",
                                       "thermal_silo", "thermal_silo_radiation"))
K, S2, PB = (_base(n) for n in ("kiln", "two_structures", "plate_on_block"))
STREAM = P.replace('fill = "random"\ncount = 2000', 'fill = "stream"\nrate = 20000.0\nmax_count = 2000')
PLANE = '\n[[walls]]\nname = "floor"\nkind = "plane"\nmaterial = "glass"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n'
FILE_SRC = P.replace('fill = "random"\ncount = 2000\nvelocity = [0.0, 0.0, -0.5]\nsize = { kind = "uniform", min = 0.0018, max = 0.0022 }\nregion = { kind = "box", lo = [0.0, 0.0, 0.05], hi = [0.06, 0.06, 0.15] }',
                 'fill = "file"\nfile = "FILE"')
TEMP_MON = '\n[[monitors]]\nname = "heat"\nkind = "temperature"\ngroup = "GROUP"\n'

# name: (base, [(old, new), ...] or a callable, expected key, via, what is broken)
SPEC = {
    # ---- unknown keys, one per table
    "unknown_case_key": (P, [('name = "pour"', 'nam = "pour"')], "case.nam", "check", "misspelt key in [case]"),
    "unknown_run_key": (P, [("duration = 0.6", "duraton = 0.6")], "run.duraton", "check", "misspelt key in [run]"),
    "unknown_dem_key": (P, [('contact = "hertz"', 'contcat = "hertz"')], "dem.contcat", "check", "misspelt key in [dem]"),
    "unknown_material_key": (P, [("E = 5.0e6", "youngs = 5.0e6")], "materials.glass.youngs", "check", "misspelt key in [materials.X]"),
    "unknown_particles_key": (P, [('name = "beads"', 'name = "beads"\ncolour = "red"')], "particles[0].colour", "check", "unknown key in [[particles]]"),
    "unknown_size_key": (D, [("radius = 0.005 }", "radus = 0.005 }")], "particles[0].size.radus", "check", "misspelt key in particles.size"),
    "unknown_region_key": (P, [("lo = [0.0, 0.0, 0.05]", "low = [0.0, 0.0, 0.05]")], "particles[0].region.low", "check", "misspelt key in particles.region"),
    "unknown_wall_key": (P, [("hi = [0.06, 0.06, 0.2]", "hieght = 0.2")], "walls[0].hieght", "check", "unknown key in [[walls]]"),
    "unknown_motion_key": (D, [("rpm = 10.0 }", "speed = 10.0 }")], "walls[0].motion.speed", "check", "unknown key in walls.motion"),
    "unknown_event_key": (H, [("{ t = 0.7 }", "{ time = 0.7 }")], "walls[1].motion.events[1].time", "check", "misspelt key in a schedule event"),
    "unknown_monitor_key": (P, [('target = "box"', 'targt = "box"')], "monitors[0].targt", "check", "misspelt key in [[monitors]]"),
    "unknown_output_key": (P, [("interval = 0.02", "intervall = 0.02")], "output.intervall", "check", "misspelt key in [output]"),
    "unknown_pairs_key": (D, [("mu = 0.5\n\n[[particles]]", "friction = 0.5\n\n[[particles]]")], "pairs[0].friction", "check", "unknown key in [[pairs]]"),
    "unknown_structure_key": (H, [('mesh = "membrane"', 'meshh = "membrane"')], "structures[0].meshh", "check", "misspelt key in [[structures]]"),
    "unknown_structure_contact_key": (H, [('contact = { tags = ["contact"]', 'contact = { tag = ["contact"]')], "structures[0].contact.tag", "check", "misspelt key in structures.contact"),
    "unknown_table": (P, [("[run]", "[runn]")], "runn", "check", "misspelt table name"),
    "unknown_quick_key": (P, [("run = { duration = 0.25 }", "run = { durration = 0.25 }")], "quick.run.durration", "check", "misspelt key in [quick]"),
    # ---- particle sizes, counts, regions
    "negative_radius": (P, [("min = 0.0018", "min = -0.0018")], "particles[0].size.min", "check", "negative radius"),
    "zero_radius": (D, [("radius = 0.005 }", "radius = 0.0 }")], "particles[0].size.radius", "check", "zero radius"),
    "radius_in_mm": (D, [("radius = 0.005 }", "radius = 5 }")], "particles[0].size.radius", "check", "radius in mm (5 instead of 0.005)"),
    "radius_in_mm_uniform": (P, [("min = 0.0018, max = 0.0022", "min = 1.8, max = 2.2")], "particles[0].size.max", "check", "radii in mm"),
    "radius_tiny_count_huge": (P, [("count = 2000", "volume_fraction = 0.2"), ("min = 0.0018, max = 0.0022", "min = 0.0000018, max = 0.0000022")], "particles[0].volume_fraction", "check", "radius in km-to-m slip: 1e13 particles"),
    "uniform_max_below_min": (P, [("min = 0.0018, max = 0.0022", "min = 0.0022, max = 0.0018")], "particles[0].size.max", "check", "max < min"),
    "uniform_missing_max": (P, [("min = 0.0018, max = 0.0022", "min = 0.0018")], "particles[0].size.max", "check", "uniform size without max"),
    "count_float_1e9": (P, [("count = 2000", "count = 1e9")], "particles[0].count", "check", "count = 1e9 (a float)"),
    "count_1e9": (P, [("count = 2000", "count = 1000000000")], "particles[0].count", "check", "count = 1e9 (MemoryError before)"),
    "random_fill_too_dense": (P, [("count = 2000", "count = 20000")], "particles[0].count", "check", "random fill far above 0.3"),
    "random_fraction_too_dense": (P, [("count = 2000", "volume_fraction = 0.5")], "particles[0].volume_fraction", "check", "random volume fraction 0.5"),
    "lattice_too_many": (D, [("count = 800", "count = 100000")], "particles[0].count", "check", "lattice count above its sites"),
    "region_outside_domain": (P, [("hi = [0.06, 0.06, 0.15]", "hi = [0.06, 0.06, 0.5]")], "particles[0].region.hi", "check", "region above the domain"),
    "region_below_domain": (P, [("lo = [0.0, 0.0, 0.05]", "lo = [-0.05, 0.0, 0.05]")], "particles[0].region.lo", "check", "region beyond domain_lo"),
    "region_inverted": (P, [("hi = [0.06, 0.06, 0.15]", "hi = [0.06, 0.06, 0.01]")], "particles[0].region.hi", "check", "region hi below lo"),
    "cylinder_region_outside": (D, [("radius = 0.099", "radius = 0.3")], "particles[0].region.centre", "check", "cylinder region wider than the domain"),
    "unknown_particle_material": (P, [('material = "glass"\nfill', 'material = "glas"\nfill')], "particles[0].material", "check", "particles of an undefined material"),
    "no_particles": (P, [("[[particles]]", "[[ignored]]")], "ignored", "check", "no [[particles]] (renamed table)"),
    # ---- streams
    "stream_rate_1e12": (STREAM, [("rate = 20000.0", "rate = 1e12")], "particles[0].rate", "check", "insertion rate 1e12/s (capped by max_count)"),
    "stream_rate_1e9_uncapped": (STREAM, [("rate = 20000.0\nmax_count = 2000", "rate = 1e9")], "particles[0].rate", "check", "uncapped stream of 6e8 particles"),
    "stream_starts_after_end": (STREAM, [("rate = 20000.0", "rate = 20000.0\nstart = 1.0")], "particles[0].start", "check", "stream starts after the run"),
    "stream_with_count": (STREAM, [("max_count = 2000", "count = 2000")], "particles[0].count", "check", "count on a stream"),
    # ---- time step and stiffness
    "dt_above_rayleigh": (P, [("seed = 7", "seed = 7\ndt = 0.01")], "run.dt", "check", "dt = 45 t_R"),
    "dt_0p7_rayleigh": (P, [("seed = 7", "seed = 7\ndt = 0.000155")], "run.dt", "check", "dt = 0.7 t_R (blows up; refused unless force_dt)"),
    "dt_linear_above_tc": (P, [('contact = "hertz"', 'contact = "linear"\nk_n = 1000.0'), ("seed = 7", "seed = 7\ndt = 0.001")], "run.dt", "check", "linear law, dt above t_c/10"),
    "linear_without_kn": (P, [('contact = "hertz"', 'contact = "linear"')], "dem.k_n", "check", "linear law without k_n"),
    "linear_kn_too_soft": (P, [('contact = "hertz"', 'contact = "linear"\nk_n = 0.001')], "dem.k_n", "check", "linear k_n = 1e-3 N/m: particles pass through each other"),
    "E_1Pa": (P, [("E = 5.0e6", "E = 1.0")], "materials.glass.E", "check", "E = 1 Pa (every particle lost)"),
    "E_1Pa_drum": (D, [("E = 1.0e7\nnu = 0.3\nrho = 2500.0\ne = 0.2\nmu = 0.3", "E = 1.0\nnu = 0.3\nrho = 2500.0\ne = 0.2\nmu = 0.3")], "materials.grain.E", "check", "E = 1 Pa in a drum"),
    "E_negative": (P, [("E = 5.0e6", "E = -5.0e6")], "materials.glass.E", "check", "negative Young's modulus"),
    "nu_half": (P, [("nu = 0.3", "nu = 0.5")], "materials.glass.nu", "check", "Poisson's ratio 0.5"),
    "skin_10m": (P, [('heat = "none"', 'heat = "none"\nskin = 10.0')], "dem.skin", "check", "Verlet skin of 10 m"),
    "duration_string": (P, [("duration = 0.6", 'duration = "0.6"')], "run.duration", "check", "a string where a number belongs"),
    "duration_absurd": (P, [("duration = 0.6", "duration = 1.0e9")], "run.duration", "check", "1e9 s: 2e13 steps"),
    "seed_float": (P, [("seed = 7", "seed = 7.5")], "run.seed", "check", "a non-integer seed"),
    "threads_negative": (P, [("seed = 7", "seed = 7\nthreads = -2")], "run.threads", "check", "negative thread count"),
    "gravity_two_components": (P, [("gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, -9.81]")], "dem.gravity", "check", "gravity with two components"),
    "domain_inverted": (P, [("domain_hi = [0.07, 0.07, 0.2]", "domain_hi = [0.07, 0.07, -0.2]")], "dem.domain_hi", "check", "domain_hi below domain_lo"),
    "contact_law_unknown": (P, [('contact = "hertz"', 'contact = "hertzian"')], "dem.contact", "check", "unknown contact law"),
    "heat_constant_without_hc": (P, [('heat = "none"', 'heat = "constant"')], "dem.h_c", "check", "constant heat model without h_c"),
    # ---- output and case
    "output_interval_above_duration": (P, [("interval = 0.02", "interval = 2.0")], "output.interval", "check", "output interval longer than the run"),
    "output_interval_below_dt": (P, [("interval = 0.02", "interval = 0.00001")], "output.interval", "check", "output interval below the DEM step"),
    "output_fields_unknown": (P, [("interval = 0.02", 'interval = 0.02\nfields = ["particles", "stress"]')], "output.fields", "check", "unknown output field"),
    "case_name_dotdot": (P, [('name = "pour"', 'name = "../x"')], "case.name", "check", "case.name = ../x writes outside out/"),
    "case_name_space": (P, [('name = "pour"', 'name = "my pour"')], "case.name", "check", "case name with a space"),
    "quick_longer": (P, [("run = { duration = 0.25 }", "run = { duration = 5.0 }")], "quick.run.duration", "check", "--quick longer than the run"),
    "quick_count_1e9": (H, [("particles = [ { count = 400 } ]", "particles = [ { count = 1000000000 } ]")], "particles[0].count", "check", "[quick] override of 1e9 particles"),
    "no_materials": (P, [("[materials.glass]", "[material.glass]")], "material", "check", "[materials] misspelt: no materials"),
    # ---- names and references
    "monitor_missing_wall": (P, [('target = "box"', 'target = "lid"')], "monitors[0].target", "check", "monitor of a wall that does not exist"),
    "monitor_missing_structure": (H, [('target = "membrane"', 'target = "membrn"')], "monitors[1].target", "check", "monitor of a structure that does not exist"),
    "monitor_missing_group": (P, [('heat = "none"', 'heat = "area"')], "monitors[2].group", "check", "temperature monitor of a missing particle group"),
    "monitor_temperature_without_heat": (P, [], "monitors[2].kind", "check", "temperature monitor without a heat model"),
    "duplicate_monitor_names": (P, [('name = "bed"', 'name = "box_load"')], "monitors[1].name", "check", "two monitors of one name"),
    "duplicate_wall_names": (D, [("[[monitors]]\nname = \"drive\"", "[[walls]]\nname = \"drum\"\nkind = \"plane\"\nmaterial = \"drum_wall\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n\n[[monitors]]\nname = \"drive\"")], "walls[1].name", "check", "two walls of one name"),
    "pairs_unknown_material": (D, [('materials = ["grain", "drum_wall"]', 'materials = ["grain", "drumwall"]')], "pairs[0].materials", "check", "pair of an undefined material"),
    # ---- walls
    "plane_rotates": (P + PLANE + 'motion = { kind = "rotation", axis = [1.0, 0.0, 0.0], centre = [0.03, 0.03, 0.0], rpm = 10.0 }\n', [], "walls[1].motion.kind", "check", "a plane that rotates"),
    "oscillation_no_frequency": (P + PLANE + 'motion = { kind = "oscillation", amplitude = 0.001 }\n', [], "walls[1].motion.frequency", "check", "an oscillation without its frequency"),
    "oscillation_with_max_speed": (P + PLANE + 'motion = { kind = "oscillation", amplitude = 0.001, frequency = 20.0, max_speed = 0.1 }\n', [], "walls[1].motion.max_speed", "check", "a servo key on an oscillation"),
    "servo_plane_without_area": (P + PLANE + 'motion = { kind = "servo", stress = 500.0, max_speed = 0.1 }\n', [], "walls[1].motion.area", "check", "a servo plane without the area of its stress"),
    "servo_two_targets": (P + PLANE + 'motion = { kind = "servo", stress = 500.0, force = 1.0, area = 0.0036, max_speed = 0.1 }\n', [], "walls[1].motion.stress", "check", "a servo with a stress and a force"),
    "servo_without_max_speed": (P + PLANE + 'motion = { kind = "servo", force = 1.0, area = 0.0036 }\n', [], "walls[1].motion.max_speed", "check", "a servo without its largest speed"),
    "servo_box_of_planes": (P, [('hi = [0.06, 0.06, 0.2]\n', 'hi = [0.06, 0.06, 0.2]\nmotion = { kind = "servo", force = 1.0, area = 0.0036, max_speed = 0.1 }\n')], "walls[0].motion.kind", "check", "a servo box of planes"),
    "servo_gain_unstable": (P + PLANE.replace('point = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]', 'point = [0.0, 0.0, 0.19]\nnormal = [0.0, 0.0, -1.0]') + 'motion = { kind = "servo", force = 1.0, area = 0.0036, max_speed = 0.1, gain = 1000.0 }\n', [], "walls[1].motion.gain", "check", "a servo gain above its stability limit"),
    "oscillation_amplitude_in_mm": (P + PLANE + 'motion = { kind = "oscillation", amplitude = 1.0, frequency = 20.0 }\n', [], "walls[1].motion.amplitude", "check", "a floor shaken with amplitude 1 (mm typed for m): 126 m/s peak, through the particles"),
    "servo_max_speed_in_mm": (P + PLANE.replace('point = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]', 'point = [0.0, 0.0, 0.19]\nnormal = [0.0, 0.0, -1.0]') + 'motion = { kind = "servo", force = 1.0, area = 0.0036, max_speed = 100.0 }\n', [], "walls[1].motion.max_speed", "check", "a servo lid of max_speed 100 (mm/s typed for m/s)"),
    "drum_rocking_in_degrees": (D, [('kind = "rotation", axis', 'kind = "oscillation", axis'), ("rpm = 10.0 }", "amplitude = 30.0, frequency = 2.0 }")], "walls[0].motion.amplitude", "check", "a drum rocked by 30 (degrees typed for rad) at 2 Hz: 38 m/s at its wall"),
    "ok_drum_rocking": (D, [('kind = "rotation", axis', 'kind = "oscillation", axis'), ("rpm = 10.0 }", "amplitude = 0.5, frequency = 1.0 }")], "-", "ok", "a drum rocked by 0.5 rad at 1 Hz"),
    "ok_oscillation_gamma_3": (P + PLANE + 'motion = { kind = "oscillation", amplitude = 0.0005, frequency = 40.0 }\n', [], "-", "ok", "a floor shaken at 0.5 mm, 40 Hz (Gamma = 3.2)"),
    "free_plane_hinged": (P + PLANE + 'motion = { kind = "free", inertia = 1.0, axis = [1.0, 0.0, 0.0], centre = [0.0, 0.0, 0.0] }\n', [], "walls[1].motion.axis", "check", "a free plane on a hinge"),
    "free_without_mass": (P + PLANE + 'motion = { kind = "free", damper = 1.0 }\n', [], "walls[1].motion.mass", "check", "a free wall without mass"),
    "free_negative_mass": (P + PLANE + 'motion = { kind = "free", mass = -1.0 }\n', [], "walls[1].motion.mass", "check", "a free wall of negative mass"),
    "wall_motion_monitor_of_a_fixed_wall": (P + '\n[[monitors]]\nname = "lid"\nkind = "wall_motion"\ntarget = "box"\n', [], "monitors[2].target", "check", "a wall_motion monitor on a wall that is not driven"),
    "box_of_planes_rotates": (P, [('hi = [0.06, 0.06, 0.2]\n', 'hi = [0.06, 0.06, 0.2]\nmotion = { kind = "rotation", axis = [0.0, 0.0, 1.0], centre = [0.03, 0.03, 0.0], rpm = 5.0 }\n')], "walls[0].motion.kind", "check", "a box of planes that rotates"),
    "plane_faces_away": (P + PLANE.replace("point = [0.0, 0.0, 0.0]", "point = [0.0, 0.0, 0.3]"), [], "walls[1].point", "check", "a plane whose inside misses the domain"),
    "rotation_rpm_and_omega": (D, [("rpm = 10.0 }", "rpm = 10.0, omega = 1.0 }")], "walls[0].motion.rpm", "check", "rotation with rpm and omega"),
    "schedule_after_end": (H, [("{ t = 0.6, velocity = [2.0, 0.0, 0.0] }, { t = 0.7 }", "{ t = 4.0, velocity = [2.0, 0.0, 0.0] }, { t = 4.1 }")], "walls[1].motion.events[0].t", "check", "schedule event after the end"),
    "schedule_not_increasing": (H, [("{ t = 0.6, velocity = [2.0, 0.0, 0.0] }, { t = 0.7 }", "{ t = 0.6, velocity = [2.0, 0.0, 0.0] }, { t = 0.5 }")], "walls[1].motion.events[1].t", "check", "schedule times decreasing"),
    "cone_outlet_wider_than_top": (H, [("outlet_radius = 0.07", "outlet_radius = 0.3")], "walls[0].outlet_radius", "check", "cone outlet wider than its top"),
    "cone_outside_domain": (H, [("centre = [0.0, 0.0, 0.3] # the outlet", "centre = [0.0, 0.0, 5.0] # the outlet")], "walls[0].centre", "check", "cone wholly outside the domain"),
    "mesh_wall_missing_file": (D, [('"../../../demos/data/drum.stl"', '"../../../demos/data/nodrum.stl"')], "walls[0].file", "check", "missing mesh file"),
    "mesh_wall_in_mm": (D, [('material = "drum_wall"\nmotion', 'scale = 1000.0\nmaterial = "drum_wall"\nmotion')], "walls[0].scale", "check", "mesh file read as mm"),
    "wall_unknown_kind": (P, [('kind = "box"             # five', 'kind = "crate"             # five')], "walls[0].kind", "check", "unknown wall kind"),
    # ---- structures
    "structure_tag_not_in_mesh": (H, [('contact = { tags = ["contact"]', 'contact = { tags = ["lid"]')], "structures[0].contact.tags[0]", "check", "contact tag not in the mesh"),
    "structure_support_not_in_mesh": (H, [('supports = ["support"]', 'supports = ["rim"]')], "structures[0].supports[0]", "check", "support tag not in the mesh"),
    "structure_tags_missing_group": (H, [('material = "rubber"      # gsi.fem', 'tags = { contact = "top_face" }\nmaterial = "rubber"      # gsi.fem')], "structures[0].tags.contact", "check", "tags mapped to a group the mesh lacks"),
    "structure_geometry_string": (H, [("radius = 0.3, thickness", 'radius = "abc", thickness')], "structures[0].geometry.radius", "check", "a string where a geometry number belongs"),
    "structure_geometry_negative": (H, [("thickness = 0.015", "thickness = -0.015")], "structures[0].geometry.thickness", "check", "negative plate thickness"),
    "structure_geometry_unknown": (H, [("radius = 0.3, thickness", "diameter = 0.6, thickness")], "structures[0].geometry.diameter", "check", "unknown builder parameter"),
    "structure_unknown_builder": (H, [('mesh = "membrane"', 'mesh = "membran"')], "structures[0].mesh", "check", "unknown mesh builder"),
    "structure_missing_file": (B, [('"../../../meshes/belt.geo"', '"../../../meshes/nobelt.geo"')], "structures[0].file", "check", "missing structure .geo file"),
    "structure_geo_string": (B, [("geometry = { length = 0.8", 'geometry = { length = "abc"')], "structures[0].geometry.length", "check", "a string for a .geo constant"),
    "structure_geo_unknown_constant": (B, [("geometry = { length = 0.8", "geometry = { lenght = 0.8")], "structures[0].geometry.lenght", "check", "misspelt .geo constant"),
    "structure_geo_tag_missing_group": (B, [('support = "belt_ends"', 'support = "ends"')], "structures[0].tags.support", "check", "tags mapped to a group the .geo lacks"),
    "thermal_contact_without_heat": (T, [('heat = "area"', 'heat = "none"')], "structures[0].contact.mode", "check", "thermal contact without a heat model"),
    # ---- radiation (dem.radiation, materials.X.emissivity)
    "radiation_emissivity_missing": (R, [("cp = 1000.0\nemissivity = 0.9\n", "cp = 1000.0\n")], "materials.clinker.emissivity", "check", "radiation on, the particles' material without an emissivity"),
    "radiation_emissivity_percent": (R, [("emissivity = 0.9", "emissivity = 90.0")], "materials.clinker.emissivity", "check", "emissivity in percent"),
    "radiation_every_unstable": (R, [("radiation_every = 50 ", "radiation_every = 500000 ")], "dem.radiation_every", "check", "radiation applied over 15 s at a time: explicit update unstable"),
    "radiation_every_float": (R, [("radiation_every = 50 ", "radiation_every = 2.5 ")], "dem.radiation_every", "check", "a non-integer evaluation interval"),
    "radiation_cutoff_below_one": (R, [("radiation_cutoff = 1.5", "radiation_cutoff = 0.5")], "dem.radiation_cutoff", "check", "a cut-off that misses touching particles"),
    "radiation_options_while_off": (R, [("radiation = true ", "radiation = false ")], "dem.radiation_cutoff", "check", "radiation options with dem.radiation = false"),
    "structure_material_unknown": (H, [('material = "rubber"      # gsi.fem', 'material = "rubbr"      # gsi.fem')], "structures[0].material", "check", "unknown FE material"),
    # ---- particle files
    "particle_file_missing": (FILE_SRC.replace("FILE", "data/nofile.csv"), [], "particles[0].file", "check", "missing particle file"),
    "particle_file_overlap": (FILE_SRC.replace("FILE", "data/overlap.csv"), [], "particles[0].file", "check", "particles overlapping by 1.8 r in a file"),
    "particle_file_bad_header": (FILE_SRC.replace("FILE", "data/bad_header.csv"), [], "particles[0].file", "check", "particle file without a radius column"),
    "particle_file_outside": (FILE_SRC.replace("FILE", "data/outside.csv"), [], "particles[0].file", "check", "particle file outside the domain"),
    "particle_file_wrong_suffix": (FILE_SRC.replace("FILE", "data/heap.txt"), [], "particles[0].file", "check", "particle file of an unknown format"),
    "particle_files_overlap_each_other": (FILE_SRC.replace("FILE", "data/heap.csv").replace("[[walls]]", '[[particles]]\nname = "again"\nmaterial = "glass"\nfill = "file"\nfile = "data/heap.csv"\n\n[[walls]]'), [], "particles[1].file", "check", "two files placing the same particles"),
    # ---- only found at set-up (gsi run)
    "file_over_lattice": (D.replace("[[walls]]", '[[particles]]\nname = "heap"\nmaterial = "grain"\nfill = "file"\nfile = "data/heap_drum.csv"\n\n[[walls]]', 1), [("[quick]\nrun = { duration = 1.0 }", "[quick]\nrun = { duration = 0.001 }\noutput = { interval = 0.001 }\nparticles = [ { count = 50 } ]")], "particles[1].file", "check", "file particles placed on a lattice fill"),
    "file_over_random_fill": (P.replace("[[walls]]", '[[particles]]\nname = "heap"\nmaterial = "glass"\nfill = "file"\nfile = "data/heap_box.csv"\n\n[[walls]]', 1), [("run = { duration = 0.25 }", "run = { duration = 0.001 }\noutput = { interval = 0.001 }")], "particles[1].file", "run", "file particles placed into a random fill (positions drawn at the start)"),
    "lattice_over_file": (D.replace("[[particles]]", '[[particles]]\nname = "heap"\nmaterial = "grain"\nfill = "file"\nfile = "data/heap_drum.csv"\n\n[[particles]]', 1), [("[quick]\nrun = { duration = 1.0 }", "[quick]\nrun = { duration = 0.001 }\noutput = { interval = 0.001 }\nparticles = [ {}, { count = 50 } ]")], "particles[1].region", "check", "a lattice fill placed over file particles"),
}

# temperature monitors: appended after the two pour monitors (monitors[2])
SPEC["monitor_missing_group"] = (P.replace("[output]", TEMP_MON.replace("GROUP", "nobody").lstrip() + "\n[output]"),
                                 [('heat = "none"', 'heat = "area"')], "monitors[2].group", "check",
                                 "temperature monitor of a missing particle group")
SPEC["monitor_temperature_without_heat"] = (P.replace("[output]", TEMP_MON.replace("GROUP", "beads").lstrip() + "\n[output]"),
                                            [], "monitors[2].kind", "check",
                                            "temperature monitor without a heat model")

DATA = {
    "overlap.csv": "x,y,z,radius\n0.03,0.03,0.05,0.002\n0.0304,0.03,0.05,0.002\n",
    "bad_header.csv": "x,y,z,r\n0.03,0.03,0.05,0.002\n",
    "outside.csv": "x,y,z,radius\n0.03,0.03,0.05,0.002\n0.03,0.03,0.5,0.002\n",
    "heap.txt": "x y z radius\n0.03 0.03 0.05 0.002\n",
    "heap.csv": "x,y,z,radius\n0.02,0.02,0.05,0.002\n0.03,0.03,0.05,0.002\n0.04,0.04,0.05,0.002\n",
    # a row of beads through the pour's random fill
    "heap_box.csv": "x,y,z,radius\n" + "".join(f"{0.004 * k + 0.004:.4f},0.03,0.1,0.002\n" for k in range(13)),
    # inside the drum, on the lattice sites of the first (lowest) layer
    "heap_drum.csv": "x,y,z,radius\n0.0,0.0101,0.03,0.005\n0.0101,0.0101,0.03,0.005\n",
}


from corpus_careful import DATA as DATA_CAREFUL, DATA_BYTES, DATA_STRUCTURES, spec, spec_structures  # noqa: E402

SPEC.update(spec(P, D, H, B, T, PLANE, FILE_SRC))
SPEC.update(spec_structures(H, B, T, K, S2, PB, D, P))
DATA.update(DATA_CAREFUL)
DATA.update(DATA_STRUCTURES)


def _write_msh(path: pathlib.Path, scale: float) -> None:
    """meshes/belt.geo meshed coarsely (h = 0.1 m) as an ASCII .msh; ``scale`` 1000 writes
    it in mm (a unit slip)."""
    import gmsh
    geo = HERE.parents[1] / "meshes" / "belt.geo"
    values = dict(length=0.8, width=0.3, thickness=0.02, h=0.1)
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(geo))
        for n in gmsh.onelab.getNames():
            last = n.rsplit("/", 1)[-1]
            if last in values:
                gmsh.onelab.setNumber(n, [values[last] * scale])
        gmsh.clear()
        gmsh.open(str(geo))
        gmsh.model.mesh.generate(3)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.option.setNumber("Mesh.Binary", 0)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


def _cases() -> dict[str, bytes]:
    """Every case file's bytes, by file name (an edit that no longer applies fails here,
    before anything in ``cases/`` is touched)."""
    out = {}
    for name, (base, edits, key, via, what) in SPEC.items():
        text = base
        for old, new in edits:
            assert old in text, (name, old)
            text = text.replace(old, new, 1)
        out[f"{name}.toml"] = f"# expect: {key} | via: {via} | {what}\n{text}".encode()
    pour = P.replace("Glass beads", "Gl\xe4ss beads").replace(
        'description = "', 'description = "Gl\xe4ss: ')
    out["non_utf8.toml"] = (b"# expect: non_utf8.toml | via: check | Latin-1 bytes in a UTF-8 file\n"
                            + pour.encode("latin-1"))
    out["not_toml.toml"] = ("# expect: not_toml.toml | via: check | a table header without its "
                            "bracket\n" + P.replace("[run]", "[run", 1)).encode()
    out["ok_case_with_bom.toml"] = (
        "\ufeff# expect: - | via: ok | a case file with a UTF-8 byte-order mark\n".encode()
        + P.encode())
    return out


def main() -> None:
    cases = _cases()
    CASES.mkdir(exist_ok=True)
    (CASES / "data").mkdir(exist_ok=True)
    for name, text in DATA.items():
        (CASES / "data" / name).write_text(text)
    for name, raw in DATA_BYTES.items():
        (CASES / "data" / name).write_bytes(raw)
    _write_msh(CASES / "data" / "belt.msh", 1.0)
    _write_msh(CASES / "data" / "belt_mm.msh", 1000.0)
    for old in CASES.glob("*.toml"):            # cases no longer in SPEC
        if old.name not in cases:
            old.unlink()
    for name, raw in cases.items():
        (CASES / name).write_bytes(raw)
    print(f"{len(cases)} cases in {CASES}")


if __name__ == "__main__":
    main()
