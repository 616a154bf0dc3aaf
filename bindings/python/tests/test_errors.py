"""Bad input raises TypeError (the wrong kind of value) or ValueError
(a wrong shape, size, range or name) with a message that says what is
wrong; nothing crashes."""

import numpy as np
import pytest
import strata

U = np.array([[0.5, 0.25]], np.float32)


@pytest.mark.parametrize(
    "call, error, words",
    [
        (lambda: strata.sample("uniform_sphere", np.array([["a", "b"]])), TypeError, "real numbers"),
        (lambda: strata.sample("uniform_sphere", np.array([[1j, 0]])), TypeError, "complex"),
        (lambda: strata.sample("uniform_sphere", [[None, 0.5]]), TypeError, "object"),
        (lambda: strata.sample("uniform_sphere", np.zeros((4, 3))), ValueError, "(..., 2)"),
        (lambda: strata.sample("uniform_ball", U), ValueError, "(..., 3)"),
        (lambda: strata.sample("uniform_sphere", [[np.nan, 0.5]]), ValueError, "NaN"),
        (lambda: strata.sample("uniform_sphere", [[1.5, 0.5]]), ValueError, "[0, 1]"),
        (lambda: strata.sample("uniform_sphere", [[-0.5, 0.5]]), ValueError, "[0, 1]"),
        (lambda: strata.pdf("uniform_sphere", [[0, 0, np.inf]]), ValueError, "finite"),
        (lambda: strata.sample("sphere", U), ValueError, "uniform_sphere"),
        (lambda: strata.sample("uniform_cone", U, cone="wide"), TypeError, "cone"),
        (lambda: strata.sample("uniform_cone", U, cone=np.nan), ValueError, "cone"),
        (lambda: strata.onb_to_world([[0, 0, 2]], [[1, 0, 0]]), ValueError, "unit length"),
        (lambda: strata.onb_to_world([[0, 0, 1]], [[1, 0, 0]], basis="mine"), ValueError, "duff"),
        (lambda: strata.onb_to_world([[0, 0, 1]], [[1, 0, 0], [0, 1, 0]]), ValueError, "shape"),
        (lambda: strata.onb_to_local([[0, 0, 1]], [[np.nan, 0, 0]]), ValueError, "finite"),
        (lambda: strata.Sobol(2).random(-1), ValueError, "at least 0"),
        (lambda: strata.Sobol(2).random(2.5), TypeError, "integer"),
        (lambda: strata.Sobol(-1), ValueError, "at least 0"),
        (lambda: strata.Sobol(2, n_max=0), ValueError, "n_max"),
        (lambda: strata.Sobol(2, seed=-1), ValueError, "seed"),
        (lambda: strata.Sobol(2, seed=2**64), ValueError, "seed"),
        (lambda: strata.Sobol(2, seed="x"), TypeError, "seed"),
        (lambda: strata.Grid(2, n_max=2**25), ValueError, "grid sampler"),
        (lambda: strata.ZSobol(2, resolution=(0, 4)), ValueError, "resolution"),
        (lambda: strata.Sobol(2).fast_forward(2**32 + 1), ValueError, "last sample index"),
        (lambda: strata.Sobol(2).random_base2(-1), ValueError, "m"),
        (lambda: strata.random_in_unit_disk(-5), ValueError, "at least 0"),
        (lambda: strata.random_in_unit_disk(5, sampler="best"), ValueError, "sobol"),
        (lambda: strata.pixel_samples([[0, 0]], [0], -1, sampler="sobol", spp=4), ValueError, "dims"),
        (lambda: strata.pixel_samples([[0, -1]], [0], 2, sampler="sobol", spp=4), ValueError, "pixels"),
        (lambda: strata.pixel_samples([[0, 0]], [0.5], 2, sampler="sobol", spp=4), TypeError, "integers"),
        (lambda: strata.pixel_samples([[0, 0], [1, 1]], [0, 1, 2], 2, sampler="sobol", spp=4), ValueError, "broadcast"),
        (lambda: strata.pixel_samples([0, 0, 0], [0], 2, sampler="sobol", spp=4), ValueError, "(..., 2)"),
        (lambda: strata.pixel_samples([[0, 0]], [0], 2, sampler="soboll", spp=4), ValueError, "unknown sampler"),
        (lambda: strata.pixel_samples([[0, 0]], [0], 2, sampler="sobol", spp=0), ValueError, "spp"),
        (lambda: strata.Spheres([[0, 0, 0]]), ValueError, "(..., 4)"),
        (lambda: strata.Spheres([[0, 0, np.inf, 1]]), ValueError, "spheres"),
        (lambda: strata.Spheres([[0, 0, 0, 1]]).closest_hit([[0, 0, 5]], [[0, 0, -2]]), ValueError, "unit length"),
        (lambda: strata.Spheres([[0, 0, 0, 1]]).any_hit([[0, 0, 5]], [[0, 0, -1]], t_max=np.nan), ValueError, "NaN"),
        (lambda: strata.Spheres([[0, 0, 0, 1]]).any_hit([[0, 0, 5]], [[0, 0, -1]], t_max=[1, 2]), ValueError, "t_max"),
        (lambda: strata.render("nowhere"), ValueError, "nowhere"),
        (lambda: strata.render(42), TypeError, "scene"),
        (lambda: strata.render(width=0), ValueError, "width"),
        (lambda: strata.render(spp=-3), ValueError, "-3"),
        (lambda: strata.render(sampler="best"), ValueError, "best"),
        (lambda: strata.render(unknown_flag=1), ValueError, "unknown-flag"),
        (lambda: strata.render(output="x.png"), ValueError, "library render"),
        (lambda: strata.render(width=8, seed=-1), ValueError, "-1"),
        (lambda: strata.render(width=8, scene_file="--spp"), ValueError, "scene-file"),
        (lambda: strata.pixel_samples([[0, 0]], [0], 2, sampler="zsobol", spp=4), ValueError, "resolution"),
        (lambda: strata.pixel_samples([[0, 0]], [0], 2, sampler="sobol", spp=4, resolution=5), TypeError, "pair"),
        (lambda: strata.Sobol(2, pixel=(1,)), TypeError, "pair"),
        (lambda: strata.Spheres([[0, 0, 0, -1]]), ValueError, "radius"),
        (lambda: strata.Spheres([[0, 0, 0, np.nan]]), ValueError, "spheres[0]"),
        (lambda: strata.render(width=8, threads=0), ValueError, "threads"),
        (lambda: strata.render(width=8, progress=3), TypeError, "callable"),
        (lambda: strata.render(width=8, seed=[1, 2]), ValueError, "seed"),
        (lambda: strata.render(width=8, spp={}), TypeError, "spp"),
    ],
)
def test_bad_input_is_refused_with_a_message(call, error, words):
    with pytest.raises(error) as caught:
        call()
    assert words in str(caught.value), str(caught.value)


def test_memory_that_cannot_exist_is_a_memory_error():
    # 2^31 rows of 2^20 float64 values: far beyond any machine. The
    # engines make their output with numpy, which refuses it.
    with pytest.raises(MemoryError):
        strata.Sobol(1 << 20, n_max=1 << 31).random(1 << 31)


def test_the_native_run_checks_its_last_index():
    from strata import _native

    s = _native.native.Sampler("independent", 16, 1, 1, 1)
    with pytest.raises(ValueError, match="pass the last index"):
        s.run_into(0, 0, 2**32 - 4096, np.empty((4097, 1)))
    s.run_into(0, 0, 2**32 - 4096, np.empty((4096, 1)))


def test_empty_and_edge_requests_work():
    assert strata.pixel_samples(np.zeros((0, 2), int), [], 3, sampler="sobol", spp=4).shape == (0, 3)
    e = strata.Sobol(3, seed=1)
    assert e.random(0).shape == (0, 3)
    e.fast_forward(2**32)
    assert e.random(0).shape == (0, 3)
    with pytest.raises(ValueError, match="last sample index"):
        e.random(1)
    last = strata.Sobol(3, seed=1).fast_forward(2**32 - 2).random(2)
    assert last.shape == (2, 3) and ((0 <= last) & (last < 1)).all()
