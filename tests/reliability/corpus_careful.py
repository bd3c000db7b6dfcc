"""The second corpus: inputs written the way a careful but hurried user gets things wrong
(units, contradictions, absurd sizes, names that are paths, duplicates, files), and a
few valid inputs next to them that must pass. ``make_corpus.py`` writes them with the
first corpus. ``via``: ``check`` (refused by ``gsi check`` in one line naming the key),
``warn`` (accepted with one ``warning:`` line naming the key), ``ok`` (accepted silently)."""
from __future__ import annotations


def spec(P, D, H, B, T, PLANE, FILE_SRC) -> dict:
    """name: (base, [(old, new), ...], key, via, what is broken)."""
    TMON = ('[[monitors]]\nname = "hot"\nkind = "temperature"\n'
            'region = { kind = "box", lo = [LO], hi = [HI] }\n\n[output]')
    MIX = ('[[monitors]]\nname = "mix"\nkind = "mixing"\ngroup = "grains"\n'
           'region = { kind = "box", lo = [-0.1, 0.0, 0.02], hi = [0.1, 0.05, 0.22] }\n'
           'cells = CELLS\n\n[output]')
    plane_at = lambda z: PLANE.replace("point = [0.0, 0.0, 0.0]", f"point = [0.0, 0.0, {z}]")
    T_HOT = ('heat_time_scale = 200.0', 'heat_time_scale = 1.0e9')
    return {
        # ---- units
        "steel_E_in_GPa": (T, [("E = 210.0e9", "E = 210.0")], "materials.steel.E", "check", "a wall's E typed in GPa"),
        "structure_E_in_MPa": (H, [('material = "rubber"      # gsi.fem', 'E = 2.0\nmaterial = "rubber"      # gsi.fem')], "structures[0].E", "check", "a structure's E override in MPa"),
        "glass_E_in_kPa": (P, [("E = 5.0e6", "E = 5.0")], "materials.glass.E", "check", "E in kPa... 5 Pa"),
        "E_above_diamond": (P, [("E = 5.0e6", "E = 5.0e15")], "materials.glass.E", "check", "E far above any solid"),
        "rho_in_g_cm3": (P, [("rho = 2500.0", "rho = 2.5")], "materials.glass.rho", "check", "density in g/cm^3"),
        "rho_in_g_cm3_drum_wall": (D, [("rho = 2500.0\ne = 0.2\nmu = 0.5", "rho = 2.5\ne = 0.2\nmu = 0.5")], "materials.drum_wall.rho", "check", "wall density in g/cm^3"),
        "rho_absurd": (P, [("rho = 2500.0", "rho = 2.5e6")], "materials.glass.rho", "check", "density 2.5e6 kg/m^3"),
        "structure_rho_in_g_cm3": (H, [('material = "rubber"      # gsi.fem', 'rho = 0.93\nmaterial = "rubber"      # gsi.fem')], "structures[0].rho", "check", "structure density in g/cm^3"),
        "convection_T_ambient_celsius": (T, [("T_ambient = 293.15", "T_ambient = 20.0")], "structures[0].thermal.convection[0].T_ambient", "warn", "ambient 20 (deg C typed for K)"),
        "particle_temperature_celsius": (T, [("temperature = 800.0", "temperature = 150.0")], "particles[0].temperature", "warn", "particles at 150 (deg C typed for K)"),
        "T_ref_celsius": (T, [("T_ref = 293.15", "T_ref = 20.0")], "structures[0].thermal.T_ref", "warn", "stress-free T of 20 (deg C)"),
        "temperature_above_5000": (T, [("temperature = 800.0", "temperature = 80000.0")], "particles[0].temperature", "check", "80,000 K (an extra zero twice)"),
        "temperature_below_1K": (T, [("temperature = 800.0", "temperature = 0.5")], "particles[0].temperature", "check", "0.5 K"),
        "cp_in_kJ": (P, [("cp = 840.0", "cp = 0.84")], "materials.glass.cp", "check", "c_p in kJ/(kg K)"),
        "k_absurd": (P, [("k = 1.0", "k = 1.0e6")], "materials.glass.k", "check", "conductivity 1e6 W/(m K)"),
        "structure_k_tiny": (T, [('material = "steel"      # E 210', 'k = 1.0e-6\nmaterial = "steel"      # E 210')], "structures[0].k", "check", "structure conductivity 1e-6"),
        "geo_overrides_in_mm": (B, [("length = 0.8, width = 0.3, thickness = 0.02", "length = 800.0, width = 300.0, thickness = 20.0")], "structures[0].geometry", "check", ".geo overrides in mm: 800 m across"),
        "membrane_radius_in_mm": (H, [("radius = 0.3, thickness", "radius = 300.0, thickness")], "structures[0].geometry.radius", "check", "a builder's radius in mm"),
        "pipe_length_in_mm": (P, [('heat = "none"', 'heat = "pipe"\npipe_length = 60.0')], "dem.pipe_length", "check", "the pipe model's slab thickness in mm"),
        # ---- names that are paths
        "monitor_name_escapes": (P, [('name = "bed"', 'name = "../../escaped"')], "monitors[1].name", "check", "monitor writes ../../escaped.csv"),
        "monitor_name_empty": (P, [('name = "bed"', 'name = ""')], "monitors[1].name", "check", "empty monitor name"),
        "monitor_name_absolute": (P, [('name = "bed"', 'name = "/tmp/bed"')], "monitors[1].name", "check", "absolute monitor name"),
        "monitor_name_backslash": (P, [('name = "bed"', 'name = "a\\\\b"')], "monitors[1].name", "check", "a Windows path as a name"),
        "monitor_name_hidden": (P, [('name = "bed"', 'name = ".bed"')], "monitors[1].name", "check", "a hidden-file name"),
        "monitor_name_long": (P, [('name = "bed"', 'name = "' + "b" * 150 + '"')], "monitors[1].name", "check", "a 150-character name"),
        "wall_name_slash": (P, [('name = "box"\nkind', 'name = "a/b"\nkind'), ('target = "box"', 'target = "a/b"')], "walls[0].name", "check", "wall a/b (file-system error at the first output)"),
        "wall_name_dotdot": (P, [('name = "box"\nkind', 'name = "../box"\nkind'), ('target = "box"', 'target = "../box"')], "walls[0].name", "check", "wall ../box"),
        "structure_name_dotdot": (H, [('name = "membrane"\nmesh', 'name = "../membrane"\nmesh')], "structures[0].name", "check", "structure ../membrane"),
        "particles_name_slash": (P, [('name = "beads"', 'name = "be/ads"')], "particles[0].name", "check", "particle group with a slash"),
        "case_name_absolute": (P, [('name = "pour"', 'name = "/tmp/pour"')], "case.name", "check", "absolute case name"),
        "wall_and_structure_same_name": (H, [('name = "gate"', 'name = "membrane"')], "structures[0].name", "check", "a wall and a structure both 'membrane'"),
        "ok_names_with_dots_dashes": (P, [('name = "bed"', 'name = "bed-1.v2_a"')], "-", "ok", "valid name with '-', '.', '_'"),
        # ---- absurd sizes
        "quick_dt_1e-9": (P, [("seed = 7", "seed = 7\ndt = 1.0e-9")], "quick.run.dt", "check", "run.dt = 1e-9: 2.5e8 steps in --quick"),
        "dt_1e-12": (P, [("seed = 7", "seed = 7\ndt = 1.0e-12")], "run.dt", "check", "run.dt = 1e-12: 6e11 steps"),
        "n_sub_1e9": (H, [('contact = { tags = ["contact"]', 'contact = { n_sub = 1000000000, tags = ["contact"]')], "structures[0].contact.n_sub", "check", "FE step of 3e5 s"),
        "n_sub_above_run": (T, [("n_sub = 50", "n_sub = 200000")], "structures[0].contact.n_sub", "check", "FE step longer than the run"),
        "geo_h_tiny": (B, [("h = 0.06, layers", "h = 0.0001, layers")], "structures[0]", "check", ".geo meshed with h = 0.1 mm"),
        "geo_h_5mm_warns": (B, [("h = 0.06, layers", "h = 0.005, layers")], "structures[0]", "warn", ".geo meshed with h = 5 mm: about 3e5 dofs"),
        "cone_facets_1e6": (H, [("facets = 48", "facets = 1000000")], "walls[0].facets", "check", "cone of 1e6 facets (MemoryError before)"),
        "cone_facets_float": (H, [("facets = 48", "facets = 1e6")], "walls[0].facets", "check", "facets as a float"),
        "checkpoint_every_step": (P, [("seed = 7", "seed = 7\ncheckpoint_interval = 1e-12")], "run.checkpoint_interval", "check", "a checkpoint every step"),
        "checkpoints_too_many": (P, [("seed = 7", "seed = 7\ncheckpoint_interval = 1e-4")], "run.checkpoint_interval", "check", "6,000 checkpoints"),
        "mixing_cells_1e12": (D, [("[output]", MIX.replace("CELLS", "[10000, 10000, 10000]"))], "monitors[2].cells", "check", "1e12 mixing cells"),
        "mixing_cells_float": (D, [("[output]", MIX.replace("CELLS", "[2.5, 2, 2]"))], "monitors[2].cells", "check", "a float where a count is meant"),
        "long_run_warns": (P, [("duration = 0.6", "duration = 6000.0"), ("interval = 0.02", "interval = 1.0"), ("run = { duration = 0.25 }", "run = { duration = 0.25 }\noutput = { interval = 0.05 }")], "run.duration", "warn", "1.4e8 steps: about 11 h of 2,000 particles"),
        "ok_checkpoint_interval": (P, [("seed = 7", "seed = 7\ncheckpoint_interval = 0.1")], "-", "ok", "six checkpoints"),
        "ok_mixing_cells": (D, [("[output]", MIX.replace("CELLS", "[4, 2, 4]"))], "-", "ok", "a mixing monitor of 32 cells"),
        # ---- geometric contradictions
        "fill_through_floor_plane": (P + plane_at(0.1), [], "particles[0].region", "check", "fill region reaching through a floor plane"),
        "fill_wholly_behind_plane": (P + plane_at(0.17), [], "particles[0].region", "check", "fill region under the floor"),
        "floor_below_domain": (P + plane_at(-0.5), [], "walls[1].point", "check", "floor outside the domain box"),
        "side_plane_outside_domain": (P + PLANE.replace("normal = [0.0, 0.0, 1.0]", "normal = [1.0, 0.0, 0.0]").replace("point = [0.0, 0.0, 0.0]", "point = [-1.0, 0.0, 0.0]"), [], "walls[1].point", "check", "a side wall 1 m outside the domain"),
        "lattice_crossing_cone": (H, [('fill = "random"\ncount = 2000', 'fill = "lattice"\ncount = 2000'), ("centre = [0.0, 0.0, 0.56], radius = 0.19, length = 0.4", "centre = [0.0, 0.0, 0.31], radius = 0.19, length = 0.5")], "particles[0].region", "check", "lattice fill through the cone and its gate"),
        "lattice_through_drum_mesh": (D, [("radius = 0.099, length = 0.05", "radius = 0.115, length = 0.05"), ("count = 800", "count = 1400")], "particles[0].region", "check", "lattice sites across the drum's mesh"),
        "temperature_monitor_outside": (T, [("[output]", TMON.replace("LO", "1.0, 1.0, 1.0").replace("HI", "2.0, 2.0, 2.0"))], "monitors[2].region", "check", "temperature monitor region outside the domain"),
        "structure_outside_domain": (B, [('tags = { contact = "belt_top"', 'translate = [0.0, 0.0, 5.0]\ntags = { contact = "belt_top"')], "structures[0].translate", "check", "a .geo structure 5 m above the domain"),
        "ok_floor_on_domain_face": (P + plane_at(-0.01), [], "-", "ok", "a floor plane on the domain's face"),
        "ok_monitor_region_inside": (T, [("[output]", TMON.replace("LO", "-0.05, -0.05, 0.0").replace("HI", "0.05, 0.05, 0.05"))], "-", "ok", "temperature monitor of the lower bed"),
        # ---- duplicates and unused keys
        "pairs_twice_reversed": (D, [("mu = 0.5\n\n[[particles]]", 'mu = 0.5\n\n[[pairs]]\nmaterials = ["drum_wall", "grain"]\nmu = 0.9\n\n[[particles]]')], "pairs[1].materials", "check", "the same pair twice, reversed, another mu"),
        "pairs_twice_same": (D, [("mu = 0.5\n\n[[particles]]", 'mu = 0.5\n\n[[pairs]]\nmaterials = ["grain", "drum_wall"]\ne = 0.4\n\n[[particles]]')], "pairs[1].materials", "check", "the same pair twice"),
        "ok_two_distinct_pairs": (D, [("mu = 0.5\n\n[[particles]]", 'mu = 0.5\n\n[[pairs]]\nmaterials = ["grain", "grain"]\nmu = 0.35\n\n[[particles]]')], "-", "ok", "two different pairs"),
        "monitor_region_on_wall_kind": (P, [('target = "box"', 'target = "box"\nregion = { kind = "box", lo = [0.0, 0.0, 0.0], hi = [0.06, 0.06, 0.05] }')], "monitors[0].region", "check", "a region on a wall monitor (ignored)"),
        "monitor_group_on_wall_kind": (P, [('target = "box"', 'target = "box"\ngroup = "beads"')], "monitors[0].group", "check", "a group on a wall monitor"),
        "monitor_target_on_particles": (P, [('kind = "particles"', 'kind = "particles"\ntarget = "box"')], "monitors[1].target", "check", "a target on a particles monitor"),
        "monitor_cells_on_particles": (P, [('kind = "particles"', 'kind = "particles"\ncells = [2, 2, 2]')], "monitors[1].cells", "check", "cells on a particles monitor"),
        "monitor_normal_on_wall": (P, [('target = "box"', 'target = "box"\nnormal = [0.0, 0.0, 1.0]')], "monitors[0].normal", "check", "a discharge normal on a wall monitor"),
        # ---- files
        "csv_T_column_rows_lack_it": (FILE_SRC.replace("FILE", "data/T_missing.csv"), [], "particles[0].file", "check", "header names T, rows lack it"),
        "csv_T_column_empty_values": (FILE_SRC.replace("FILE", "data/T_empty.csv"), [], "particles[0].file", "check", "T values left empty"),
        "csv_T_absurd": (FILE_SRC.replace("FILE", "data/T_absurd.csv"), [], "particles[0].file", "check", "T column of 60,000 K"),
        "csv_row_too_long": (FILE_SRC.replace("FILE", "data/row_long.csv"), [], "particles[0].file", "check", "a row with a value the header lacks"),
        "ok_csv_with_bom": (FILE_SRC.replace("FILE", "data/bom_heap.csv"), [], "-", "ok", "a particle CSV with a UTF-8 byte-order mark (Excel)"),
        # ---- heat stability known before the run
        "heat_time_scale_1e9": (T, [T_HOT], "run.heat_time_scale", "check", "heat update unstable at the first contact (stopped at step 690 before)"),
        "heat_radius_time_scale_1e9": (T, [T_HOT, ('heat = "area"', 'heat = "radius"')], "run.heat_time_scale", "check", "the same with the radius model"),
        "heat_constant_hc_huge": (P, [('heat = "none"', 'heat = "constant"\nh_c = 1.0e5')], "dem.h_c", "check", "constant conductance 100 kW/K between 2 mm beads"),
        # ---- friction beyond the range where the explicit step is stable (drum: mu_pp = 100
        # blew up at step 413 at dt = 0.23 t_R; mu = 30 at step 449; 1, 3, 10 and mu = 100 at
        # dt = 7e-5 s ran)
        "drum_mu_pp_100": (D, [("mu = 0.3\nmu_r", "mu = 100.0\nmu_r")], "materials.grain.mu", "check", "mu_pp = 100 at dt = 0.23 t_R (blew up at step 413)"),
        "drum_mu_pp_30": (D, [("mu = 0.3\nmu_r", "mu = 30.0\nmu_r")], "materials.grain.mu", "check", "mu_pp = 30 at dt = 0.23 t_R (blew up at step 449)"),
        "drum_pair_mu_100": (D, [("mu = 0.5\n\n[[particles]]", 'mu = 0.5\n\n[[pairs]]\nmaterials = ["grain", "grain"]\nmu = 100.0\n\n[[particles]]')], "pairs[1].mu", "check", "a grain-grain pair of mu = 100"),
        "ok_drum_mu_pp_10": (D, [("mu = 0.3\nmu_r", "mu = 10.0\nmu_r")], "-", "ok", "mu_pp = 10 (ran)"),
        "ok_drum_mu_pp_100_small_dt": (D, [("mu = 0.3\nmu_r", "mu = 100.0\nmu_r"), ("dt = 1.0e-4 ", "dt = 7.0e-5 ")], "-", "ok", "mu_pp = 100 at dt = 0.16 t_R (ran)"),
        "ok_heat_time_scale_1e3": (T, [("heat_time_scale = 200.0", "heat_time_scale = 1000.0")], "-", "ok", "a stable heat-time scale"),
    }


DATA = {
    "T_missing.csv": "x,y,z,radius,T\n0.02,0.02,0.05,0.002\n0.03,0.03,0.05,0.002\n0.04,0.04,0.05,0.002\n"
                     "0.02,0.04,0.05,0.002\n0.04,0.02,0.05,0.002\n",
    "T_empty.csv": "x,y,z,radius,T\n0.02,0.02,0.05,0.002,\n0.03,0.03,0.05,0.002,\n",
    "T_absurd.csv": "x,y,z,radius,T\n0.02,0.02,0.05,0.002,60000\n0.03,0.03,0.05,0.002,300\n",
    "row_long.csv": "x,y,z,radius\n0.02,0.02,0.05,0.002,300\n0.03,0.03,0.05,0.002\n",
}
#: written as bytes (a UTF-8 byte-order mark first)
DATA_BYTES = {
    "bom_heap.csv": b"\xef\xbb\xbfx,y,z,radius\n0.02,0.02,0.05,0.002\n0.03,0.03,0.05,0.002\n",
}


def spec_structures(H, B, T, K, S2, PB, D, P) -> dict:
    """FE structures: where their bodies lie (outside the domain, through the particles
    placed at the start) and the size of their meshes (every builder and gmsh file gets an
    estimate in ``gsi check``). Bases: H hopper_membrane (membrane builder), B belt_hopper
    (a .geo), T thermal_silo (silo), K kiln (drum), S2 two_structures (hopper + membrane),
    PB plate_on_block (two boxes, a particle file), D drum (an STL wall turning at 10 rpm),
    P pour."""
    MEM = 'mesh = "membrane"\ngeometry'
    CONE_FILL = ('fill = "random"\ncount = 2000\nsize = { kind = "single", radius = 0.01 }\n'
                 'region = { kind = "cylinder", centre = [0.0, 0.0, 0.56], radius = 0.19, length = 0.4 }')
    HOP = 'translate = [0.0, 0.0, 0.3]'
    BELT = 'tags = { contact = "belt_top"'
    MSH = (B, [('file = "../../../meshes/belt.geo"', 'file = "data/belt.msh"'),
               ("geometry = { length = 0.8, width = 0.3, thickness = 0.02, h = 0.06, layers = 1 }\n", "")])
    KILN_MESH = 'mesh = "drum"'
    PLATE = "length_z = 0.01, h = 0.01 }"
    SHELL = ('mesh = "hopper"\ngeometry = { top_radius = 0.24, outlet_radius = 0.07, height = 0.3, thickness = 0.005, h = 0.04 }\ntranslate = [0.0, 0.0, 0.3]',
             'mesh = "shell"\ngeometry = { radius = 0.2, height = 0.2, thickness = 0.005, hopper_height = 0.1, outlet_radius = 0.07, h = 0.04 }\ntranslate = [0.0, 0.0, 0.4]')
    return {
        # ---- a structure through the particles placed at the start
        "membrane_through_fill": (H, [(MEM, 'mesh = "membrane"\ntranslate = [0.0, 0.0, 0.7]\ngeometry')], "particles[0].region", "check", "the membrane builder's plate through the random fill"),
        "hopper_structure_through_fill": (S2, [(HOP, "translate = [0.0, 0.0, 0.7]")], "particles[0].region", "check", "the hopper builder's shell through the fill"),
        "geo_belt_through_fill": (B, [(BELT, "translate = [0.0, 0.0, 0.5]\n" + BELT)], "particles[0].region", "check", "a .geo belt moved into the fill's cylinder"),
        "silo_wall_through_fill": (T, [("radius = 0.045, length = 0.1", "radius = 0.06, length = 0.1")], "particles[0].region", "check", "a fill wider than the silo builder's wall"),
        "kiln_lattice_through_shell": (K, [("radius = 0.059, length = 0.115", "radius = 0.07, length = 0.115")], "particles[0].region", "check", "lattice sites inside the drum builder's shell"),
        "file_particles_inside_block": (PB, [('"../../../demos/data/plate_particles.csv"', '"data/inside_block.csv"')], "particles[0].file", "check", "particle file rows inside the block structure"),
        "file_particle_cut_by_plate": (PB, [('"../../../demos/data/plate_particles.csv"', '"data/cut_by_plate.csv"')], "particles[0].file", "check", "a row 2 mm above the plate, radius 5 mm"),
        "msh_through_fill": (MSH[0], MSH[1] + [(BELT, "translate = [0.0, 0.0, 0.5]\n" + BELT)], "particles[0].region", "check", "a .msh belt through the fill"),
        "ok_fill_resting_on_membrane": (H, [("centre = [0.0, 0.0, 0.56], radius = 0.19, length = 0.4", "centre = [0.0, 0.0, 0.016], radius = 0.06, length = 0.2"), ("count = 2000", "count = 100"), ("particles = [ { count = 400 } ]", "particles = [ { count = 50 } ]")], "-", "ok", "a fill region standing on the membrane (centres a radius above it)"),
        "ok_plate_particles_touching": (PB, [], "-", "ok", "file particles resting on the plate (distance = radius)"),
        "ok_msh_structure": (MSH[0], MSH[1], "-", "ok", "a structure from a .msh file"),
        # ---- a structure outside the domain
        "membrane_outside_domain": (H, [(MEM, 'mesh = "membrane"\ntranslate = [0.0, 0.0, 5.0]\ngeometry')], "structures[0].translate", "check", "a builder's membrane 5 m above the domain"),
        "kiln_shell_outside_domain": (K, [(KILN_MESH, KILN_MESH + "\ntranslate = [1.0, 0.0, 0.0]")], "structures[0].translate", "check", "the drum builder's shell 1 m beside the domain"),
        "msh_in_mm": (B, [('file = "../../../meshes/belt.geo"', 'file = "data/belt_mm.msh"'), ("geometry = { length = 0.8, width = 0.3, thickness = 0.02, h = 0.06, layers = 1 }\n", "")], "structures[0].file", "check", "a .msh written in mm: 800 m across"),
        # ---- a builder's values refused only when meshing before (at the run's start)
        "hopper_structure_outlet_wider": (S2, [("top_radius = 0.24, outlet_radius = 0.07, height = 0.3", "top_radius = 0.24, outlet_radius = 0.3, height = 0.3")], "structures[0].geometry.outlet_radius", "check", "a hopper structure whose outlet is wider than its top"),
        "membrane_shape_misspelt": (H, [('shape = "circle"', 'shape = "circel"')], "structures[0].geometry.shape", "check", "a misspelt membrane shape"),
        # ---- the mesh size of every builder
        "membrane_h_tiny": (H, [("h = 0.06, n_thickness", "h = 0.0002, n_thickness")], "structures[0].geometry.h", "check", "membrane builder at h = 0.2 mm: 3e8 dofs"),
        "membrane_h_5mm_warns": (H, [("h = 0.06, n_thickness", "h = 0.005, n_thickness")], "structures[0].geometry.h", "warn", "membrane builder at h = 5 mm: about 5e5 dofs"),
        "silo_h_tiny": (T, [("bottom = \"flat\", h = 0.008", "bottom = \"flat\", h = 0.00005")], "structures[0].geometry.h", "check", "silo builder at h = 0.05 mm"),
        "kiln_drum_h_tiny": (K, [("thickness = 0.005, h = 0.012", "thickness = 0.005, h = 0.00005")], "structures[0].geometry.h", "check", "drum builder at h = 0.05 mm"),
        "hopper_h_tiny": (S2, [("thickness = 0.005, h = 0.04", "thickness = 0.005, h = 0.0002")], "structures[0].geometry.h", "check", "hopper builder at h = 0.2 mm"),
        "box_h_tiny": (PB, [("length_z = 0.05, h = 0.0125", "length_z = 0.05, h = 0.0001")], "structures[1].geometry.h", "check", "box builder at h = 0.1 mm: 5e8 cells"),
        "box_n_huge": (PB, [(PLATE, "length_z = 0.01, n = [2000, 2000, 200] }")], "structures[0].geometry.n", "check", "box builder of 8e8 cells given by n"),
        "ok_box_by_n": (PB, [(PLATE, "length_z = 0.01, n = [10, 10, 1] }")], "-", "ok", "box builder given its cells"),
        "ok_shell_structure": (S2, [SHELL], "-", "ok", "the shell builder (its own dof count; a thickness passed before gave a TypeError)"),
        # ---- walls moving faster than the particles' stiffness allows (the overlap of a
        # particle hit at the wall's surface speed, as the stiffness check for free fall)
        "drum_rpm_1e6": (D, [("rpm = 10.0 }", "rpm = 1.0e6 }")], "walls[0].motion.rpm", "check", "a drum at 1e6 rpm (1e4 m/s at its wall)"),
        "gate_velocity_2000": (H, [("velocity = [2.0, 0.0, 0.0]", "velocity = [2000.0, 0.0, 0.0]")], "walls[1].motion.events[0].velocity", "check", "a gate opening at 2 km/s (mm/s typed as m/s)"),
        "ok_drum_rpm_60": (D, [("rpm = 10.0 }", "rpm = 60.0 }")], "-", "ok", "a drum at 60 rpm"),
        # ---- errors that named the wrong key before (the material's E)
        "gravity_in_mm": (P, [("gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, 0.0, -9810.0]")], "dem.gravity", "check", "g in mm/s^2 (refused before as 'glass E too soft')"),
        "velocity_in_mm": (P, [("velocity = [0.0, 0.0, -0.5]", "velocity = [0.0, 0.0, -500.0]")], "particles[0].velocity", "check", "an initial speed in mm/s (refused before as 'glass E too soft')"),
        "ok_gravity_centrifuge_50g": (P, [("gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, 0.0, -490.5]"), ("E = 5.0e6", "E = 5.0e8")], "-", "ok", "a centrifuge at 50 g"),
        # ---- a traction above the structure's modulus
        "traction_above_E": (H, [('supports = ["support"]   # the clamped rim', 'supports = ["support"]   # the clamped rim\nloads = [ { tag = "contact", traction = [0.0, 0.0, -5.0e9] } ]')], "structures[0].loads[0].traction", "check", "a 5 GPa traction on a rubber membrane (E 2 MPa)"),
        "ok_traction_500Pa": (H, [('supports = ["support"]   # the clamped rim', 'supports = ["support"]   # the clamped rim\nloads = [ { tag = "contact", traction = [0.0, 0.0, -500.0] } ]')], "-", "ok", "a 500 Pa traction on the membrane"),
        # ---- the extrapolation's sizes (kiln: 2 h of 0.5 s periods replayed)
        "kiln_periods_1e12": (K, [("periods = 14400 ", "periods = 1000000000000 ")], "extrapolation.periods", "check", "1e12 periods replayed: about 1e5 h (ran until killed)"),
        "kiln_cells_1e9": (K, [("cells = 200\n", "cells = 1000000000\n")], "extrapolation.cells", "check", "1e9 Voronoi cells for 640 particles"),
        # ---- random fills and particle files against shaped walls (lattices were checked)
        "random_fill_through_cone": (H, [("centre = [0.0, 0.0, 0.56], radius = 0.19, length = 0.4", "centre = [0.0, 0.0, 0.31], radius = 0.19, length = 0.5")], "particles[0].region", "check", "a random fill through the cone and its gate"),
        "random_fill_through_funnel": (B, [("centre = [0.0, 0.0, 0.45], radius = 0.14", "centre = [0.0, 0.0, 0.3], radius = 0.14")], "particles[0].region", "check", "a random fill through the funnel's cone"),
        "file_row_cut_by_cone": (H, [(CONE_FILL, 'fill = "file"\nfile = "data/cone_cut.csv"'), ("particles = [ { count = 400 } ]", "")], "particles[0].file", "check", "a particle file row on the cone's surface"),
        "ok_file_rows_inside_cone": (H, [(CONE_FILL, 'fill = "file"\nfile = "data/cone_ok.csv"'), ("particles = [ { count = 400 } ]", "")], "-", "ok", "particle file rows inside the cone"),
        "ok_random_fill_above_cone": (H, [("centre = [0.0, 0.0, 0.56], radius = 0.19", "centre = [0.0, 0.0, 0.62], radius = 0.3"), ("radius = 0.3, length = 0.4", "radius = 0.3, length = 0.35")], "-", "ok", "a random fill wider than the cone, wholly above its rim"),
    }


DATA_STRUCTURES = {
    # plate_on_block: the block spans z in [-0.0495, 0.0005], the plate [0, 0.01]
    "inside_block.csv": "x,y,z,radius,T\n-0.03,-0.03,0.015,0.005,800\n0.0,0.0,-0.02,0.005,800\n",
    "cut_by_plate.csv": "x,y,z,radius,T\n-0.03,-0.03,0.015,0.005,800\n0.01,0.01,0.012,0.005,800\n",
    # hopper_membrane's cone: radius 0.07 + (z - 0.3) 0.17/0.3, i.e. 0.155 at z = 0.45
    "cone_cut.csv": "x,y,z,radius\n0.0,0.0,0.45,0.01\n0.155,0.0,0.45,0.01\n",
    "cone_ok.csv": "x,y,z,radius\n0.0,0.0,0.45,0.01\n0.1,0.0,0.45,0.01\n",
}
