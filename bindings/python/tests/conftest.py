"""Shared test data: the value locks and golden rows the Rust tests
export (core/tests/data/locks.json, std-runner/tests/data/golden.json),
and the locks' hash."""

import json
import pathlib

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
CORE_DATA = ROOT / "core" / "tests" / "data"


@pytest.fixture(scope="session")
def locks():
    return json.loads((CORE_DATA / "locks.json").read_text())


@pytest.fixture(scope="session")
def golden():
    return json.loads((ROOT / "std-runner" / "tests" / "data" / "golden.json").read_text())


def fnv(*arrays):
    """FNV-1a 64 over 32-bit words (little-endian bytes), the arrays'
    rows interleaved: row i of the first, row i of the second, ... (the
    locks hash each point's values together)."""
    rows = np.concatenate(
        [np.ascontiguousarray(a).view(np.uint32).reshape(len(a), -1) for a in arrays], axis=1
    )
    h = 0xCBF29CE484222325
    for byte in rows.astype("<u4").tobytes():
        h = ((h ^ byte) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def grid():
    """The locks' 97 x 97 grid over [0, 1)^2, edges included: rows of
    (i / 96, j / 96), the last value the largest float below 1."""
    t = np.arange(97, dtype=np.float32) / np.float32(96)
    t[96] = np.nextafter(np.float32(1), np.float32(0))
    i, j = np.meshgrid(t, t, indexing="ij")
    return np.stack([i.ravel(), j.ravel()], axis=1)


def spheres_csv(name):
    rows = []
    for line in (CORE_DATA / name).read_text().splitlines():
        if "x" in line:
            continue
        values = line.split(",")[:4]
        if len(values) == 4:
            rows.append([np.float32(v) for v in values])
    return np.array(rows, dtype=np.float32)


class Pcg32:
    """PCG32 (pcg-c-basic's srandom and random): the tracing lock's ray
    generator, as rand_pcg's Pcg32::new(state, stream)."""

    MASK = (1 << 64) - 1

    def __init__(self, state, stream):
        self.inc = ((stream << 1) | 1) & self.MASK
        self.state = (state + self.inc) & self.MASK
        self.state = (self.state * 6364136223846793005 + self.inc) & self.MASK

    def next_u32(self):
        old = self.state
        self.state = (old * 6364136223846793005 + self.inc) & self.MASK
        xs = (((old >> 18) ^ old) >> 27) & 0xFFFFFFFF
        rot = old >> 59
        return ((xs >> rot) | (xs << ((-rot) & 31))) & 0xFFFFFFFF

    def next_f32(self):
        return np.float32(self.next_u32() >> 8) * np.float32(1.0 / 16777216.0)
