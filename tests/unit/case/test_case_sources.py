"""Particle sources: file round trips (CSV, VTU written by ParticleWriter), group ids, and
the pre-run checks (each message names its key)."""
import numpy as np
import pytest

from gsi.case.sources import MAX_PARTICLES, ParticleSource, Size, read_particle_file
from gsi.config.schema import load
from gsi.dem import Material, ParticleWriter, Simulation
from gsi.errors import GsiInputError

DOM = dict(domain_lo=(0.0, 0.0, 0.0), domain_hi=(0.1, 0.1, 0.1))


def _sim(seed=0):
    return Simulation({"m": Material(E=5e6, nu=0.3, rho=2500)}, dt=1e-5, skin=2e-4,
                      domain=(DOM["domain_lo"], DOM["domain_hi"]), gravity=(0, 0, 0), seed=seed)


def _source(**kw):
    table = dict(material="m", fill="random", count=20,
                 size={"kind": "uniform", "min": 1e-3, "max": 1.5e-3},
                 region={"kind": "box", "lo": [0.01, 0.01, 0.01], "hi": [0.05, 0.05, 0.05]})
    table.update(kw)
    return load(ParticleSource, {k: v for k, v in table.items() if v is not None}, "particles[0]")


def _random_particles(sim, rng):
    ids = _source().add_to(sim, rng=rng)
    sim.v[:] = rng.normal(size=(sim.n, 3))      # distinct velocities to read back
    sim.T[:] = rng.uniform(300, 400, sim.n)
    return ids


def test_vtu_round_trip_through_particle_writer(tmp_path):
    rng = np.random.default_rng(1)
    sim = _sim()
    _random_particles(sim, rng)
    path = ParticleWriter(tmp_path / "out").write(sim)
    src = load(ParticleSource, {"material": "m", "fill": "file",
                                "file": f"out/{path.name}"}, "particles[1]")
    src.check("particles[1]", base_dir=tmp_path, **DOM)
    sim2 = _sim()
    ids = src.add_to(sim2, rng=rng, base_dir=tmp_path)
    assert len(ids) == sim.n
    np.testing.assert_array_equal(sim2.x, sim.x)
    np.testing.assert_array_equal(sim2.radius, sim.radius)
    np.testing.assert_array_equal(sim2.v, sim.v)
    np.testing.assert_array_equal(sim2.T, sim.T)


def test_csv_round_trip_with_and_without_optional_columns(tmp_path):
    rng = np.random.default_rng(2)
    sim = _sim()
    _random_particles(sim, rng)
    full = np.column_stack([sim.x, sim.radius, sim.v, sim.T])
    np.savetxt(tmp_path / "p.csv", full, delimiter=",", header="x,y,z,radius,vx,vy,vz,T",
               comments="", fmt="%.17g")
    np.savetxt(tmp_path / "q.csv", full[:, [3, 0, 1, 2]], delimiter=",", header="radius,x,y,z",
               comments="", fmt="%.17g")
    sim2 = _sim()
    src = _source(fill="file", file="p.csv", count=None, size=None, region=None)
    src.add_to(sim2, rng=rng, base_dir=tmp_path)
    for a, b in ((sim2.x, sim.x), (sim2.radius, sim.radius), (sim2.v, sim.v), (sim2.T, sim.T)):
        np.testing.assert_array_equal(a, b)
    src = _source(fill="file", file="q.csv", count=None, size=None, region=None,
                  velocity=[0.0, 0.0, -1.0], temperature=350.0)
    sim3 = _sim()
    src.add_to(sim3, rng=rng, base_dir=tmp_path)
    np.testing.assert_array_equal(sim3.x, sim.x)
    assert (sim3.v == [0.0, 0.0, -1.0]).all() and (sim3.T == 350.0).all()


def test_stream_group_ids_are_the_inserted_particles():
    sim = _sim()
    first = _source().add_to(sim, rng=np.random.default_rng(0))
    src = _source(fill="stream", count=None, rate=2000.0, start=1e-3, max_count=7)
    ins = src.add_to(sim, rng=np.random.default_rng(0))
    assert len(ins.ids) == 0
    sim.step(401)                    # past 4 ms: 6 due after the start at 1 ms
    assert len(ins.ids) == ins.n_inserted == 6 and sim.n == 26
    assert set(ins.ids).isdisjoint(first) and set(ins.ids) | set(first) == set(sim.ids)
    assert src.group(3) == "particles3" and _source(name="glass").group(3) == "glass"


@pytest.mark.parametrize("kw, match", [
    (dict(count=None), r"^particles\[0\]\.count: give exactly one of count or volume_fraction"),
    (dict(fill="stream"), r"^particles\[0\]\.count: not used by fill = 'stream'.*max_count"),
    (dict(fill="stream", count=None), r"^particles\[0\]\.rate: missing"),
    (dict(fill="file", count=None), r"^particles\[0\]\.size: not used by fill = 'file'"),
    (dict(size={"kind": "single", "min": 1e-3}), r"^particles\[0\]\.size\.radius: missing"),
    (dict(size={"kind": "single", "radius": 1e-3, "std": 1e-4}),
     r"^particles\[0\]\.size\.std: not a key of size kind 'single'"),
])
def test_keys_that_do_not_match_the_fill(kw, match):
    with pytest.raises(GsiInputError, match=match):
        _source(**kw)


@pytest.mark.parametrize("kw, match", [
    # a radius in mm: does not fit the region / over a third of the domain
    (dict(size={"kind": "single", "radius": 2.0}), r"^particles\[0\]\.size\.radius: .*did you give mm"),
    (dict(size={"kind": "uniform", "min": 1e-3, "max": 0.035},
          region={"kind": "box", "lo": [0, 0, 0], "hi": [0.1, 0.1, 0.1]}),
     r"^particles\[0\]\.size\.max: radius 0\.035 m is over a third of the domain.*mm"),
    (dict(count=40_000_000), r"^particles\[0\]\.count: 40000000 particles is more than 2e\+07"),
    (dict(count=None, volume_fraction=0.45), r"^particles\[0\]\.volume_fraction: \d+ particles fill 0\.45"),
    (dict(count=5000), r"^particles\[0\]\.count: 5000 particles fill 0\.\d\d .* jams near 0\.3"),
    (dict(fill="lattice", count=3000), r"^particles\[0\]\.count: 3000 particles do not fit the 2197 lattice"),
    (dict(region={"kind": "box", "lo": [0.01, 0.01, 0.01], "hi": [0.05, 0.05, 0.15]}),
     r"^particles\[0\]\.region\.hi = .*outside dem\.domain"),
    (dict(fill="stream", count=None, rate=100.0, start=2.0), r"^particles\[0\]\.start = 2\.0: .*after the end"),
    (dict(fill="stream", count=None, rate=1e9), r"^particles\[0\]\.rate: the stream would insert"),
    (dict(fill="file", count=None, size=None, region=None, file="nope.csv"),
     r"^particles\[0\]\.file = '.*nope\.csv': no such file"),
])
def test_checks_name_the_key(kw, match):
    src = _source(**kw)
    with pytest.raises(GsiInputError, match=match):
        src.check("particles[0]", duration=1.0, **DOM)


def test_check_passes_what_builds():
    src = _source(fill="lattice", count=1000, size={"kind": "single", "radius": 1.9e-3})
    src.check("particles[0]", duration=1.0, **DOM)
    assert len(src.add_to(_sim(), rng=np.random.default_rng(0))) == 1000
    assert src.planned_count() < MAX_PARTICLES


def test_bad_files_name_the_key(tmp_path):
    (tmp_path / "h.csv").write_text("x,y,z\n0.1,0.1,0.1\n")
    (tmp_path / "n.csv").write_text("x,y,z,radius\n0.05,0.05,abc,0.001\n")
    (tmp_path / "o.csv").write_text("x,y,z,radius\n0.05,0.05,0.2,0.001\n")
    (tmp_path / "b.vtu").write_text("<VTKFile>not really</VTKFile>")
    for name, match in (("h.csv", "lacks radius"), ("n.csv", "not numbers"),
                        ("o.csv", "reach outside the domain"), ("b.vtu", "cannot read")):
        src = _source(fill="file", file=name, count=None, size=None, region=None)
        with pytest.raises(GsiInputError, match=rf"^particles\[0\]\.file = '{name}': .*{match}"):
            src.check("particles[0]", base_dir=tmp_path, duration=1.0, **DOM)
    (tmp_path / "p.txt").write_text("x,y,z,radius\n")
    with pytest.raises(GsiInputError, match=r"^src\.file = 'p\.txt': must end in \.csv or \.vtu"):
        read_particle_file(tmp_path / "p.txt", key="src.file", shown="p.txt")


def test_size_mean_volume_matches_sampling():
    rng = np.random.default_rng(9)
    for size in (Size(kind="uniform", min=1e-3, max=2e-3), Size(kind="normal", mean=1e-3, std=2e-4),
                 Size(kind="discrete", values=(1e-3, 2e-3), weights=(3.0, 1.0))):
        r = size.distribution().sample(rng, 400_000)
        assert size.mean_volume() == pytest.approx((4 / 3 * np.pi * r ** 3).mean(), rel=5e-3)


def test_absurd_counts_refused_before_allocation():
    sim = _sim()
    for kw in (dict(fill="lattice", count=None, size={"kind": "single", "radius": 1e-5}),
               dict(count=None, volume_fraction=0.2, size={"kind": "single", "radius": 1e-5})):
        src = _source(**kw)
        with pytest.raises(GsiInputError, match=r"^particles\[0\]\.(size|volume_fraction): \d+ "
                                                r"particles is more than 2e\+07"):
            src.add_to(sim, rng=np.random.default_rng(0), path="particles[0]")
    assert sim.n == 0
