"""relief.trace against the CLI's relief trace, far origins, t_max, threads and the GL backend."""
import numpy as np
import pytest

import relief
from conftest import assert_same_hits, read_hits_csv, run_cli, write_rays_csv


def random_rays(hf, n, seed=7):
    rng = np.random.default_rng(seed)
    origins = np.column_stack([rng.uniform(-10, hf.width + 10, n), rng.uniform(-10, hf.height + 10, n),
                               rng.uniform(hf.depth + 1, hf.depth + 30, n)])
    targets = np.column_stack([rng.uniform(0, hf.width, n), rng.uniform(0, hf.height, n),
                               np.zeros(n)])
    return origins.astype(np.float32), (targets - origins).astype(np.float32)


@pytest.mark.parametrize("technique", ["exact", "cone", "quadtree", "linear"])
def test_trace_equals_cli(cli, tmp_path, technique):
    hf = relief.Heightfield.generate("fbm", 48, 40, seed=3, depth=6.0)
    origins, directions = random_rays(hf, 300)
    # Far origins too: both bring them to the box the same way.
    origins[:5] -= 1e7 * directions[:5] / np.linalg.norm(directions[:5], axis=1, keepdims=True)
    write_rays_csv(tmp_path / "rays.csv", origins, directions)
    code, _, err = run_cli(cli, "trace", "gen:fbm:48x40:3", "--depth", 6, "-t", technique,
                           "--rays", tmp_path / "rays.csv", "-o", tmp_path / "hits.csv")
    assert code == 0, err
    expected = read_hits_csv(tmp_path / "hits.csv")
    hits = relief.trace(hf, origins, directions, technique=technique)
    assert len(hits) == len(expected)
    np.testing.assert_array_equal(hits["hit"], expected["hit"] == 1)
    np.testing.assert_array_equal(hits["steps"], expected["steps"].astype(np.int32))
    both = hits["hit"]
    np.testing.assert_allclose(hits["t"][both], expected["t"][both], rtol=1e-6)
    np.testing.assert_allclose(hits["point"][both],
                               np.column_stack([expected["x"], expected["y"], expected["z"]])[both],
                               rtol=1e-6, atol=1e-4)
    assert np.all(np.isinf(hits["t"][~both])) and np.all(np.isnan(hits["point"][~both]))


def test_dtypes_layouts_and_threads(fbm):
    origins, directions = random_rays(fbm, 200)
    reference = relief.trace(fbm, origins, directions, technique="exact")
    # float64, a non-contiguous view, integer-like lists: the same rays, the same hits.
    wide = np.zeros((200, 6))
    wide[:, ::2] = origins
    same = relief.trace(fbm, wide[:, ::2], directions.astype(np.float64), technique="exact",
                        threads=1)
    assert_same_hits(same, reference)
    listed = relief.trace(fbm, origins.tolist(), directions.tolist(), technique="exact", threads=3)
    assert_same_hits(listed, reference)
    assert reference.dtype.names == ("hit", "t", "point", "steps", "fetches")
    assert reference["hit"].any() and (reference["fetches"] > 0).any()


def test_t_max(fbm):
    origins, directions = random_rays(fbm, 200)
    free = relief.trace(fbm, origins, directions, technique="cone")
    assert free["hit"].sum() > 50
    limit = np.where(free["hit"], free["t"] - 0.5, np.inf)
    cut = relief.trace(fbm, origins, directions, technique="cone", t_max=limit)
    assert not cut["hit"].any()
    half = relief.trace(fbm, origins, directions, technique="cone", t_max=float(np.median(free["t"][free["hit"]])))
    assert 0 < half["hit"].sum() < free["hit"].sum()
    assert np.all(half["t"][half["hit"]] <= np.median(free["t"][free["hit"]]))


def test_technique_parameters(fbm):
    origins, directions = random_rays(fbm, 100)
    capped = relief.trace(fbm, origins, directions, technique="linear", max_steps=4, binary_steps=2)
    assert capped["steps"].max() <= 4 + 2  # linear steps, then the binary refinement
    kebab = relief.trace(fbm, origins, directions, technique="linear", **{"max-steps": 4, "binary-steps": 2})
    assert_same_hits(capped, kebab)


def test_gl_backend_agrees_with_cpu(fbm):
    origins, directions = random_rays(fbm, 200)
    cpu = relief.trace(fbm, origins, directions, technique="exact")
    try:
        gl = relief.trace(fbm, origins, directions, technique="exact", backend="gl")
    except RuntimeError as e:  # no EGL display at all (the GL tests skip the same way)
        pytest.skip(f"no GL backend here: {e}")
    stats = relief.compare(cpu, gl)
    assert stats["wrong"] == 0 and stats["error"]["max"] < 1e-3
