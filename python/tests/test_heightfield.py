"""Heightfield: loaders, generators, arrays, and the numpy view of its samples."""
import json

import numpy as np
import pytest

import relief
from conftest import run_cli


def test_heights_are_a_view(fbm):
    view = fbm.heights
    assert view.shape == (fbm.height, fbm.width) and view.dtype == np.float32
    assert view.base is fbm and np.shares_memory(view, fbm.heights)
    origins = np.array([[10.5, 12.5, fbm.depth + 5.0]])
    down = np.array([[0.0, 0.0, -1.0]])
    before = relief.trace(fbm, origins, down, technique="exact")
    # Writing through numpy changes the surface the next trace sees: a flat floor at 0.
    hash_before = fbm.content_hash
    view[:] = 0.0
    after = relief.trace(fbm, origins, down, technique="exact")
    assert fbm.content_hash != hash_before
    assert after["hit"][0] and after["point"][0][2] == pytest.approx(0.0, abs=1e-5)
    assert before["point"][0][2] > 0.0
    del view  # the view kept the heightfield alive; nothing else to check but no crash


def test_view_outlives_its_heightfield():
    view = relief.Heightfield.generate("sine", 16, 8).heights
    assert float(view.sum()) > 0.0


def test_load_matches_the_cli_loader(tmp_path, cli):
    hf = relief.Heightfield.load("gen:peaks6:40x30:2", depth=5.0, crop=(4, 3, 20, 10))
    assert (hf.width, hf.height, hf.depth) == (20, 10, 5.0)
    assert hf.source == "gen:peaks6:40x30:2@crop=4,3,20,10"
    repeat = relief.Heightfield.load("gen:fbm:32x32", edge="repeat", depth_ratio=0.25)
    assert repeat.edge == "repeat" and repeat.depth == pytest.approx(8.0)
    # The CLI's info reads the same file the same way: same size.
    code, out, _ = run_cli(cli, "info", "gen:peaks6:40x30:2@crop=4,3,20,10", "--format", "json")
    info = json.loads(out)
    assert code == 0 and (info["width"], info["height"]) == (20, 10)
    assert int(info["hash"], 16) == hf.content_hash


def test_generate_matches_load():
    a = relief.Heightfield.generate("fbm", 32, 24, seed=5)
    b = relief.Heightfield.load("gen:fbm:32x24:5")
    np.testing.assert_array_equal(a.heights, b.heights)
    assert a.content_hash == b.content_hash


def test_from_array():
    data = np.linspace(0.0, 1.0, 12, dtype=np.float64).reshape(3, 4)
    hf = relief.Heightfield.from_array(data, depth=2.0)
    np.testing.assert_allclose(hf.heights, data, rtol=1e-7)
    assert not np.shares_memory(hf.heights, data)
    # Any layout and dtype: a transposed integer array, rescaled by its own range.
    ints = np.arange(12, dtype=np.int16).reshape(4, 3).T
    scaled = relief.Heightfield.from_array(ints, normalize=True)
    assert scaled.heights.shape == (3, 4)
    assert scaled.heights.min() == 0.0 and scaled.heights.max() == 1.0
    ranged = relief.Heightfield.from_array(data * 10.0, height_range=(0.0, 10.0))
    np.testing.assert_allclose(ranged.heights, data, rtol=1e-6)
