"""The renderer from Python: images, films, scenes from files, progress,
Ctrl-C, and the GIL released while native code works."""

import _thread
import sys
import threading
import time

import numpy as np
import pytest
import strata
from conftest import ROOT


def test_an_image_is_its_films_mean_and_a_crop_is_its_window():
    film = strata.render("cover", width=40, height=24, spp=4, seed=3, film=True)
    img = strata.render("cover", width=40, height=24, spp=4, seed=3)
    assert img.shape == (24, 40, 3) and img.dtype == np.float32
    assert np.array_equal(film.rgb(), img)
    sums = film.sums()
    assert sums.dtype == np.int64 and sums.shape == (24, 40, 4)
    mean = sums[..., :3] / sums[..., 3:4]
    assert np.allclose(mean, img, rtol=1e-5, atol=1e-6)
    assert (film.samples() == 4).all() and (film.dropped() == 0).all()
    # A crop renders the same pixels as the whole frame there.
    part = strata.render("cover", width=40, height=24, spp=4, seed=3, pixel_bounds=(8, 24, 4, 12))
    assert np.array_equal(part, img[4:12, 8:24])


def test_a_splatted_filter_keeps_its_margin_in_the_film_only():
    # Lanczos has negative lobes: its samples are splatted into the
    # pixels around them, so a cropped window's film holds a margin.
    film = strata.render("week09", width=32, height=18, spp=4, filter="lanczos", pixel_bounds=(4, 28, 2, 16), film=True)
    x, y, w, h = film.window
    assert (w, h) == (24, 14) and x > 0 and y > 0
    assert film.shape == (h + 2 * y, w + 2 * x)
    part = film.rgb()
    assert part.shape == (14, 24, 3)
    # Pixels a margin inside the window have all their samples: they are
    # the whole frame's, exactly.
    whole = strata.render("week09", width=32, height=18, spp=4, filter="lanczos")
    m = x
    assert np.array_equal(part[m : h - m, m : w - m], whole[2 + m : 16 - m, 4 + m : 28 - m])


def test_scenes_come_from_toml_files_too():
    path = ROOT / "examples" / "scenes" / "materials.toml"
    a = strata.render(path, width=24, height=16, spp=2, film=True)
    b = strata.render(str(path), width=24, height=16, spp=2, film=True, threads=1)
    assert a.hash() == b.hash() and a.shape == (16, 24)


def test_adaptive_renders_vary_their_samples():
    film = strata.render("caustics", width=32, height=18, adaptive=0.0004, min_spp=16, max_spp=64, film=True)
    s = film.samples()
    assert s.min() >= 16 and s.max() <= 64 and s.min() < s.max()


def test_progress_reports_pixel_samples_up_to_the_total():
    seen = []
    strata.render("week09", width=64, height=36, spp=8, tile=8, threads=2, progress=lambda d, t: seen.append((d, t)))
    total = 64 * 36 * 8
    assert seen and seen[-1] == (total, total)
    assert all(t == total for _, t in seen)
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)
    # A slow callback still gets the last count.
    slow = []

    def cb(done, total):
        slow.append(done)
        time.sleep(0.05)

    strata.render("week09", width=64, height=36, spp=8, threads=2, progress=cb)
    assert slow[-1] == total


def test_passes_of_samples_add_up_to_the_one_shot_film():
    # 600 spp in 32-pixel tiles renders in three passes of sample indices
    # (256 + 256 + 88); in 2-pixel tiles in one. The films are the same.
    for filt in ("box", "lanczos"):
        passes = strata.render("cover", width=20, height=12, spp=600, tile=32, filter=filt, film=True)
        one = strata.render("cover", width=20, height=12, spp=600, tile=2, filter=filt, film=True)
        assert passes.hash() == one.hash(), filt
        assert (passes.samples() == 600).all()


def test_an_exception_in_progress_stops_the_render():
    class Enough(Exception):
        pass

    def progress(done, total):
        if done > 0:
            raise Enough

    with pytest.raises(Enough):
        strata.render("cover", width=400, height=225, spp=1024, tile=8, progress=progress)


def test_ctrl_c_stops_a_long_render():
    # A render of minutes in 32-pixel tiles; Ctrl-C (as Python's signal
    # handler sees it) arrives once it has started. It must stop with
    # KeyboardInterrupt before the last pixel sample: within a pass.
    seen = []

    def progress(done, total):
        if not seen:
            threading.Timer(0.05, _thread.interrupt_main).start()
        seen.append(done)

    with pytest.raises(KeyboardInterrupt):
        strata.render("cover", width=400, height=225, spp=65536, progress=progress)
    assert seen[-1] < 400 * 225 * 65536


def _other_thread_runs_during(call):
    """How many steps a Python thread takes while `call` runs, with
    forced switches of the GIL turned off: it can run only if the call
    lets go of the GIL."""
    steps, stop = [0], threading.Event()

    def spin():
        while not stop.is_set():
            steps[0] += 1
            time.sleep(0)  # lets the GIL go, so the caller gets it back

    old = sys.getswitchinterval()
    t = threading.Thread(target=spin)
    t.start()
    try:
        sys.setswitchinterval(1000.0)
        before = steps[0]
        call()
        after = steps[0]
    finally:
        sys.setswitchinterval(old)
        stop.set()
        t.join()
    return after - before


def test_native_work_releases_the_gil():
    pixels = np.zeros((1 << 20, 2), np.uint32)
    indices = np.arange(1 << 20, dtype=np.uint32)
    for call in (
        lambda: strata.pixel_samples(pixels, indices, 16, sampler="halton", spp=1 << 20),
        lambda: strata.Sobol(16, seed=1).random(1 << 20),
        lambda: strata.sample("uniform_sphere", np.full((1 << 22, 2), 0.5, np.float32)),
    ):
        # Hundreds of steps where the GIL is free (each step waits for it).
        assert _other_thread_runs_during(call) > 50
    # Control: a call that holds the GIL (numpy's sort of a large array
    # of Python objects) lets through at most the one forced switch a
    # wait begun under the old interval may still make.
    objs = np.array([str(i) for i in range(200_000)], dtype=object)
    assert _other_thread_runs_during(lambda: np.sort(objs)) <= 1
