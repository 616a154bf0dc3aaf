"""Strata from Python: deterministic sampling and tracing over numpy arrays.

The values are those of Strata's Rust core, bit for bit: samplers
(:class:`Sobol`, :class:`Halton`, :class:`Independent`,
:class:`Stratified`, :class:`Grid`, :class:`ZSobol`, SciPy QMC engines),
the renderer's own pixel samples (:func:`pixel_samples`), mappings with
pdfs and inverses (:func:`sample`, :func:`pdf`, :func:`invert`),
orthonormal bases (:func:`onb_to_world`, :func:`onb_to_local`), the
course's helpers (:func:`random_in_unit_disk`, :func:`random_in_unit_ball`,
:func:`random_unit_vectors`), spheres in a BVH (:class:`Spheres`) and the
path tracer (:func:`render`). Every call takes and returns whole arrays
and releases the GIL while it works.

>>> import strata
>>> x = strata.Sobol(2, seed=7).random(1024)
>>> x.shape, bool(((0 <= x) & (x < 1)).all())
((1024, 2), True)
"""

from __future__ import annotations

import os

import numpy as np

from ._native import native as _strata
from ._arrays import U32_MAX, count, floats, pair, seed_of, uints
from ._engines import (
    ENGINES,
    HAVE_SCIPY,
    N_MAX,
    Grid,
    Halton,
    Independent,
    Sobol,
    Stratified,
    ZSobol,
)

__version__ = _strata.__version__

__all__ = [
    "Film",
    "Grid",
    "Halton",
    "Independent",
    "MAPPINGS",
    "N_MAX",
    "SAMPLERS",
    "Sobol",
    "Spheres",
    "Stratified",
    "ZSobol",
    "invert",
    "onb_to_local",
    "onb_to_world",
    "output_revision",
    "pdf",
    "pixel_samples",
    "random_in_unit_ball",
    "random_in_unit_disk",
    "random_unit_vectors",
    "render",
    "sample",
    "simd_level",
]

#: The sampler kinds, by name.
SAMPLERS = tuple(_strata.sampler_kinds())
#: The mappings, by name: ``uniform_sphere``, ``uniform_hemisphere``,
#: ``cosine_hemisphere``, ``concentric_disk``, ``polar_disk``,
#: ``uniform_ball``, ``uniform_cone`` (``cone`` = cos θmax) and
#: ``uniform_cone_sin2`` (``cone`` = sin² θmax, exact for tiny cones).
MAPPINGS = tuple(_strata.mapping_names())

Film = _strata.Film


def simd_level() -> str:
    """The SIMD level of the native module in use: ``"avx2"`` where the
    CPU runs x86-64-v3 code, else ``"sse2"`` (the portable build; set
    ``STRATA_SIMD=portable`` to choose it); ``"neon"`` on aarch64. Values
    never depend on it."""
    return _strata.simd()


def output_revision() -> int:
    """Changes whenever a seeded render's pixels change."""
    return _strata.output_revision()


# ------------------------------------------------------------ samplers


def pixel_samples(pixels, indices, dims, *, sampler, spp, seed=0, resolution=None):
    """The first ``dims`` dimensions of pixel samples, as a render draws
    them: sample ``indices[...]`` of pixel ``pixels[..., :]`` (x, y) of the
    ``sampler`` kind built for ``spp`` samples per pixel and ``seed``
    (``resolution`` = (width, height) of the image: ``zsobol`` needs it,
    the other kinds ignore it). ``pixels`` has shape ``(..., 2)``, ``indices`` broadcasts
    against its leading shape; the result is float32 ``(..., dims)``:
    dimensions 0 and 1 are the position in the pixel, then 2-D pairs, then
    a 1-D value when ``dims`` is odd.

    >>> import strata
    >>> rows = strata.pixel_samples([[3, 4], [3, 4]], [0, 1], 4, sampler="sobol", spp=16)
    >>> rows.shape, str(rows.dtype)
    ((2, 4), 'float32')
    """
    dims = count(dims, "dims", high=1 << 20)
    spp = count(spp, "spp", low=1, high=U32_MAX)
    seed = seed_of(seed)
    p = uints(pixels, "pixels")
    if p.ndim == 0 or p.shape[-1] != 2:
        raise ValueError(f"pixels: expected shape (..., 2), not {p.shape}")
    i = uints(indices, "indices")
    try:
        lead = np.broadcast_shapes(p.shape[:-1], i.shape)
    except ValueError:
        raise ValueError(
            f"indices of shape {i.shape} do not broadcast against pixels of shape {p.shape}"
        ) from None
    p = np.ascontiguousarray(np.broadcast_to(p, lead + (2,)).reshape(-1, 2))
    i = np.ascontiguousarray(np.broadcast_to(i, lead).reshape(-1))
    if resolution is not None:
        width, height = pair(resolution, "resolution", low=1)
    elif sampler == "zsobol":
        # ZSobol' orders the image's pixels along one curve: its values
        # depend on the resolution, which the pixels given cannot tell.
        raise ValueError("the zsobol sampler needs resolution=(width, height)")
    else:
        width = height = 1  # the other kinds treat every pixel alike
    s = _strata.Sampler(sampler, spp, seed, width, height)
    out = np.empty((len(i), dims), np.float32)
    s.fill_into(p, i, out)
    return out.reshape(lead + (dims,))


# ------------------------------------------------------------ mappings


def _map(op, mapping, values, cone):
    if mapping not in MAPPINGS:
        raise ValueError(f"unknown mapping {mapping!r}: one of {', '.join(MAPPINGS)}")
    u_cols, p_cols = _strata.mapping_arity(mapping)
    if isinstance(cone, (bool, np.bool_)) or not isinstance(cone, (int, float, np.floating, np.integer)):
        raise TypeError(f"cone must be a real number, not {type(cone).__name__}")
    rows, lead = floats(values, "u" if op == "sample" else "points", u_cols if op == "sample" else p_cols)
    out = _strata.map(op, mapping, float(cone), rows)
    return out.reshape(lead) if op == "pdf" else out.reshape(lead + (out.shape[1],))


def sample(mapping, u, *, cone=0.0):
    """Maps samples ``u`` (shape ``(..., 2)``, ``(..., 3)`` for the ball; in
    ``[0, 1]``) to points of ``mapping`` (see :data:`MAPPINGS`): float32
    ``(..., 3)``, ``(..., 2)`` for the disks. ``cone`` is the cone's cos θmax
    (sin² θmax for ``uniform_cone_sin2``).

    >>> import strata
    >>> d = strata.sample("cosine_hemisphere", [[0.5, 0.25]])
    >>> bool(d[0, 2] > 0)
    True
    """
    return _map("sample", mapping, u, cone)


def pdf(mapping, points, *, cone=0.0):
    """The density of each point of ``mapping`` (per steradian, per unit
    area or per unit volume, as the domain): float32 of the leading shape."""
    return _map("pdf", mapping, points, cone)


def invert(mapping, points, *, cone=0.0):
    """The samples that :func:`sample` maps to ``points``."""
    return _map("invert", mapping, points, cone)


def _onb(to_world, normals, dirs, basis):
    n, lead = floats(normals, "normals", 3)
    d, lead_d = floats(dirs, "dirs", 3)
    if lead != lead_d:
        raise ValueError(f"normals and dirs differ in shape: {lead + (3,)} and {lead_d + (3,)}")
    return _strata.onb(to_world, basis, n, d).reshape(lead + (3,))


def onb_to_world(normals, dirs, *, basis="duff"):
    """Directions given in the orthonormal basis about each unit normal
    (``z`` along it) in world space. ``basis`` is ``"duff"`` (Duff et al.
    2017, right-handed) or ``"axis_switch"`` (the course's). Normals that
    are not unit length are refused."""
    return _onb(True, normals, dirs, basis)


def onb_to_local(normals, dirs, *, basis="duff"):
    """The inverse of :func:`onb_to_world`."""
    return _onb(False, normals, dirs, basis)


# ------------------------------------------------------------ the course's helpers


def _course_points(n, seed, sampler, dims):
    n = count(n, "n", high=U32_MAX)
    if sampler not in ENGINES:
        raise ValueError(f"unknown sampler {sampler!r}: one of {', '.join(SAMPLERS)}")
    if n == 0:
        return np.zeros((0, dims), np.float32)
    u = ENGINES[sampler](dims, seed=seed, n_max=n).random(n)
    return u.astype(np.float32)  # exact: the values are float32's


def random_in_unit_disk(n, seed=0, *, sampler="independent"):
    """``n`` points uniform in the unit disk, float32 ``(n, 2)``.

    The course draws them one at a time by rejection::

        def random_vec3_in_unit_disk():
            while True:
                p = Vec3(random.uniform(-1, 1), random.uniform(-1, 1), 0)
                if p.length_squared() < 1:
                    return p

    Here the ``sampler``'s points (one pixel, indices ``0..n``) go through
    the concentric map, which keeps their stratification: deterministic
    for a seed, no loop, and a ``sobol`` sampler gives evenly spread
    points.
    """
    return sample("concentric_disk", _course_points(n, seed, sampler, 2))


def random_in_unit_ball(n, seed=0, *, sampler="independent"):
    """``n`` points uniform in the unit ball, float32 ``(n, 3)``: the
    course's ``random_vec3_in_unit_sphere`` (a rejection loop over the
    cube) as one mapping of 3-D samples."""
    return sample("uniform_ball", _course_points(n, seed, sampler, 3))


def random_unit_vectors(n, seed=0, *, sampler="independent"):
    """``n`` directions uniform on the unit sphere, float32 ``(n, 3)``: the
    course's ``random_vec3_unit`` (a point of the ball, normalised) as one
    area-preserving map of 2-D samples."""
    return sample("uniform_sphere", _course_points(n, seed, sampler, 2))


# ------------------------------------------------------------ tracing


class Spheres:
    """Spheres in a BVH, for closest-hit and any-hit queries over ray
    arrays. Hits equal the brute-force loop's over the spheres, bit for
    bit (ties to the lowest index).

    >>> import strata
    >>> s = strata.Spheres([[0, 0, -3, 1]])
    >>> t, ids = s.closest_hit([0, 0, 0], [0, 0, -1])  # one ray: 0-d arrays
    >>> float(t), int(ids)
    (2.0, 0)
    """

    def __init__(self, spheres=None, *, centers=None, radii=None):
        """``spheres`` as rows of ``x, y, z, radius``, or ``centers``
        ``(n, 3)`` and ``radii`` ``(n,)``."""
        if spheres is None:
            if centers is None or radii is None:
                raise ValueError("give spheres, or centers and radii")
            c, lead = floats(centers, "centers", 3)
            r = np.asarray(radii)
            if r.dtype.kind not in "fiu":
                raise TypeError(f"radii: expected real numbers, not dtype {r.dtype}")
            if r.shape != lead:
                raise ValueError(f"radii of shape {r.shape} for centers of shape {lead + (3,)}")
            spheres = np.concatenate([c, r.reshape(-1, 1).astype(np.float32)], axis=1)
        rows, _ = floats(spheres, "spheres", 4)
        self._tree = _strata.Spheres(rows)

    def __len__(self):
        return len(self._tree)

    @staticmethod
    def _rays(origins, dirs, t_min, t_max):
        o, lead = floats(origins, "origins", 3)
        d, lead_d = floats(dirs, "dirs", 3)
        if lead != lead_d:
            raise ValueError(f"origins and dirs differ in shape: {lead + (3,)}, {lead_d + (3,)}")
        n = o.shape[0]
        bounds = []
        for name, v in (("t_min", t_min), ("t_max", t_max)):
            b = np.asarray(v)
            if b.dtype.kind not in "fiu":
                raise TypeError(f"{name}: expected real numbers, not dtype {b.dtype}")
            try:
                b = np.broadcast_to(b, lead).reshape(n)
            except ValueError:
                raise ValueError(f"{name} of shape {b.shape} does not fit rays of shape {lead}") from None
            bounds.append(b.astype(np.float32).reshape(n, 1))
        rows = np.concatenate([o, d] + bounds, axis=1)
        return np.ascontiguousarray(rows, dtype=np.float32), lead

    def closest_hit(self, origins, dirs, t_min=0.0, t_max=np.inf):
        """The closest hit of each ray ``origins + t · dirs`` with ``t`` in
        ``(t_min, t_max)`` (directions must be unit length): ``(t, ids)``
        arrays of the rays' shape, ``ids`` the sphere's index or -1 (then
        ``t`` is infinite)."""
        rows, lead = self._rays(origins, dirs, t_min, t_max)
        t, ids = self._tree.closest_hit(rows)
        return t.reshape(lead), ids.reshape(lead)

    def any_hit(self, origins, dirs, t_min=0.0, t_max=np.inf):
        """Whether each ray hits any sphere within ``(t_min, t_max)``."""
        rows, lead = self._rays(origins, dirs, t_min, t_max)
        return self._tree.any_hit(rows).reshape(lead)


# ------------------------------------------------------------ rendering

def render(scene="week09", *, threads=None, progress=None, film=False, **settings):
    """Renders ``scene`` (a built-in name or a TOML file's path) with the
    settings of ``strata render``, given as keywords: ``width``,
    ``height``, ``spp``, ``sampler``, ``seed``, ``filter``, ``max_depth``,
    ``adaptive``, ``crop``... (``--max-depth 8`` is ``max_depth=8``;
    ``True`` gives a bare flag, a tuple a comma list such as ``crop=(0,
    0.5, 0, 0.5)``, a ``range`` the sample range ``samples=range(0, 8)``). They pass the command line's one check; its message is the
    ``ValueError``.

    Returns the image as float32 linear RGB of shape ``(height, width,
    3)``, or with ``film=True`` the exact film (:class:`Film`: its
    ``rgb()``, integer ``sums()``, ``samples()`` and ``hash()``, the golden
    table's hash). ``threads`` defaults to the CPUs available; pixels never
    depend on it. ``progress(done, total)`` is called with the pixel
    samples rendered as the render goes. It renders in passes of sample
    indices (their exact films add up to the one-shot film, bit for bit):
    Ctrl-C stops it once the passes of the tiles in flight finish and
    raises ``KeyboardInterrupt`` (an adaptive render is one pass).

    >>> import strata
    >>> img = strata.render("week09", width=32, height=18, spp=4, sampler="sobol")
    >>> img.shape, str(img.dtype)
    ((18, 32, 3), 'float32')
    """
    if not isinstance(scene, (str, os.PathLike)):
        raise TypeError(f"scene must be a name or a path, not {type(scene).__name__}")
    # `--flag=value`: a value that starts with '-' stays a value.
    flags = ["--scene=" + os.fspath(scene)]
    for key, value in settings.items():
        flag = "--" + key.replace("_", "-")
        if isinstance(value, (bool, np.bool_)):
            if value:
                flags.append(flag)
        elif value is None:
            continue
        elif isinstance(value, (str, int, float, np.integer, np.floating, os.PathLike)):
            flags.append(f"{flag}={os.fspath(value) if isinstance(value, os.PathLike) else value}")
        elif isinstance(value, range):
            if value.step != 1:
                raise ValueError(f"{key}=: a range of step 1, not {value}")
            flags.append(f"{flag}={value.start}..{value.stop}")
        elif isinstance(value, (tuple, list)):
            flags.append(f"{flag}={','.join(str(v) for v in value)}")
        else:
            raise TypeError(f"{key}= takes a number, a string or a bool, not {type(value).__name__}")
    if threads is None:
        cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
        threads = min(cpus, 512)  # the runner's limit
    threads = count(threads, "threads", low=1, high=65535)
    if progress is not None and not callable(progress):
        raise TypeError("progress must be callable as progress(done, total)")
    result = _strata.render(flags, threads, progress)
    return result if film else result.rgb()
