"""The package against the core's value locks and the golden table, bit
for bit: samplers, mappings, bases, hits and renders' film sums."""

import numpy as np
import pytest
import strata
from conftest import Pcg32, fnv, grid, spheres_csv

# The kinds as the locks build them: 16 spp, seed 2026; ZSobol' over a
# 320 x 180 image, and at 256 spp over 2^20 x 2^20 pixels.
KINDS = {
    "independent": ("independent", 16, None),
    "grid": ("grid", 16, None),
    "stratified": ("stratified", 16, None),
    "sobol": ("sobol", 16, None),
    "halton": ("halton", 16, None),
    "zsobol": ("zsobol", 16, (320, 180)),
    "zsobol_wide": ("zsobol", 256, (1 << 20, 1 << 20)),
}


@pytest.mark.parametrize("name", list(KINDS))
def test_pixel_samples_reproduce_the_rows_lock(locks, name):
    kind, spp, resolution = KINDS[name]
    k = np.arange(64)
    pixels = np.stack([37 * k % 320, 11 * k % 180], axis=1)
    rows = strata.pixel_samples(
        pixels, k % 16, 7, sampler=kind, spp=spp, seed=2026, resolution=resolution or (320, 180)
    )
    assert rows.dtype == np.float32 and rows.shape == (64, 7)
    assert fnv(rows) == int(locks["sampler_rows_fnv"]["rows_" + name], 16)


@pytest.mark.parametrize("name", list(KINDS))
def test_positions_reproduce_the_first_values_lock(locks, name):
    kind, spp, resolution = KINDS[name]
    p = strata.pixel_samples(
        [12, 34], 5, 2, sampler=kind, spp=spp, seed=2026, resolution=resolution or (320, 180)
    )
    assert p.view(np.uint32).tolist() == locks["sampler_first_values"][name][:2]


@pytest.mark.parametrize("name", ["independent", "sobol", "halton", "zsobol"])
def test_an_engine_is_one_pixel_of_the_renderers_sampler(name):
    kind, spp, _ = KINDS[name]
    e = strata.ENGINES[kind](7, seed=2026, n_max=spp, pixel=(12, 34), resolution=(320, 180))
    points = e.random(spp)
    rows = strata.pixel_samples(
        [12, 34], np.arange(spp), 7, sampler=kind, spp=spp, seed=2026, resolution=(320, 180)
    )
    assert points.dtype == np.float64
    assert np.array_equal(points, rows.astype(np.float64))


def test_mappings_reproduce_their_locks(locks):
    want = {k: int(v, 16) for k, v in locks["mapping_fnv"].items()}
    u = grid()
    for name in ("uniform_sphere", "uniform_hemisphere", "cosine_hemisphere"):
        pts = strata.sample(name, u)
        got = fnv(pts, strata.invert(name, pts), strata.pdf(name, pts))
        assert got == want[name], name
    for name in ("concentric_disk", "polar_disk"):
        pts = strata.sample(name, u)
        assert fnv(pts, strata.invert(name, pts)) == want[name], name
    cone = strata.sample("uniform_cone", u, cone=np.float32(0.3))
    tiny = strata.sample("uniform_cone_sin2", u, cone=np.float32(1e-7))
    got = fnv(
        cone,
        strata.invert("uniform_cone", cone, cone=np.float32(0.3)),
        tiny,
        strata.invert("uniform_cone_sin2", tiny, cone=np.float32(1e-7)),
    )
    assert got == want["uniform_cone"]
    normals = strata.sample("uniform_sphere", u)
    dirs = np.tile(np.array([0.3, -0.2, 0.9], np.float32), (len(u), 1))
    got = fnv(
        strata.onb_to_world(normals, dirs),
        strata.onb_to_world(normals, dirs, basis="axis_switch"),
    )
    assert got == want["onb"]
    # The third coordinate runs along the grid's diagonal (float32 maths).
    u3 = np.concatenate([u, ((u[:, 0] + u[:, 1]) * np.float32(0.5))[:, None]], axis=1)
    ball = strata.sample("uniform_ball", u3)
    got = fnv(ball, strata.invert("uniform_ball", ball), strata.pdf("uniform_ball", ball))
    assert got == want["uniform_ball"]


@pytest.mark.parametrize(
    "name, file, lo, hi",
    [
        ("course", "course.csv", (-2.0, -0.5, -2.0), (2.0, 1.0, 1.0)),
        ("cover", "cover.csv", (-11.0, 0.0, -11.0), (11.0, 2.0, 11.0)),
    ],
)
def test_hits_reproduce_the_tracing_lock(locks, name, file, lo, hi):
    # 4096 rays from PCG32(3): origins in [lo, hi], directions uniform on
    # the sphere, normalised as glam does (times 1 / sqrt(x² + y² + z²)).
    rng = Pcg32(3, int(locks["pcg_stream"], 16))
    lo, hi = np.array(lo, np.float32), np.array(hi, np.float32)
    origins = np.empty((4096, 3), np.float32)
    u = np.empty((4096, 2), np.float32)
    for i in range(4096):
        origins[i] = [lo[k] + (hi[k] - lo[k]) * rng.next_f32() for k in range(3)]
        u[i] = [rng.next_f32(), rng.next_f32()]
    d = strata.sample("uniform_sphere", u)
    len2 = d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2]
    dirs = d * (np.float32(1) / np.sqrt(len2))[:, None]
    tree = strata.Spheres(spheres_csv(file))
    t, ids = tree.closest_hit(origins, dirs)
    hit = tree.any_hit(origins, dirs)
    assert np.array_equal(hit, ids >= 0)
    words = np.stack(
        [
            ids.astype(np.uint32),
            np.where(ids >= 0, t.view(np.uint32), 0).astype(np.uint32),
            hit.astype(np.uint32),
        ],
        axis=1,
    )
    assert fnv(words) == int(locks["tracing_fnv"][name], 16)


def test_every_golden_row_renders_its_film(golden):
    flags = golden["flags"]
    settings = {flags[k][2:].replace("-", "_"): int(flags[k + 1]) for k in range(0, len(flags), 2)}
    assert len(golden["films"]) >= 30
    for key, want in golden["films"].items():
        scene, sampler = key.split("/")
        film = strata.render(scene, sampler=sampler, threads=2, film=True, **settings)
        assert film.hash() == int(want, 16), key
        assert film.shape == (settings["height"], settings["width"])
        assert (film.samples() == settings["spp"]).all()


def test_a_golden_render_is_the_same_on_any_thread_count_and_tile(golden):
    flags = golden["flags"]
    settings = {flags[k][2:].replace("-", "_"): int(flags[k + 1]) for k in range(0, len(flags), 2)}
    want = int(golden["films"]["cover/sobol"], 16)
    for threads, tile in [(1, 32), (3, 8), (2, 5)]:
        film = strata.render("cover", sampler="sobol", threads=threads, tile=tile, film=True, **settings)
        assert film.hash() == want, (threads, tile)
