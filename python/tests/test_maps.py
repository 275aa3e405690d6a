"""bake, Maps save/load, stale maps refused as by the CLI, maps as numpy arrays."""
import numpy as np
import pytest

import relief
from conftest import assert_same_hits, run_cli


def test_bake_save_load_round_trip(tmp_path, fbm):
    maps = relief.bake(fbm, "cone")
    assert maps.techniques == ["cone"]
    arrays = maps.arrays
    assert arrays and all(a.dtype == np.float32 and a.ndim == 3 for a in arrays.values())
    assert not next(iter(arrays.values())).flags.writeable
    path = tmp_path / "maps.exr"
    maps.save(str(path))
    loaded = relief.Maps.load(str(path), fbm)
    for name, array in arrays.items():
        np.testing.assert_array_equal(loaded.arrays[name], array)
    assert loaded.parameters == maps.parameters and loaded.source == maps.source
    origins, directions = relief.camera_rays(fbm, size=(24, 16))
    built = relief.trace(fbm, origins, directions, technique="cone")
    baked = relief.trace(fbm, origins, directions, technique="cone", maps=loaded)
    assert_same_hits(built, baked)


def test_cli_reads_python_maps_and_back(tmp_path, cli, fbm):
    relief.bake(fbm, "quadtree").save(str(tmp_path / "py.exr"))
    code, _, err = run_cli(cli, "bake", "gen:fbm:48x40:3", "--maps", "quadtree", "-o", tmp_path / "cli.exr")
    assert code == 0, err
    ours = relief.Maps.load(str(tmp_path / "py.exr"), fbm).arrays
    theirs = relief.Maps.load(str(tmp_path / "cli.exr"), fbm).arrays
    assert ours.keys() == theirs.keys()
    for name in ours:
        np.testing.assert_array_equal(ours[name], theirs[name])


def test_stale_maps_refused(tmp_path, cli, fbm):
    path = tmp_path / "maps.exr"
    relief.bake(fbm, "cone").save(str(path))
    other = relief.Heightfield.generate("fbm", 48, 40, seed=4)
    with pytest.raises(ValueError) as e:
        relief.Maps.load(str(path), other)
    code, _, err = run_cli(cli, "trace", "gen:fbm:48x40:4", "-t", "cone", "--maps", path, "--rays", "-")
    assert code == 3 and err.strip() == "relief: error: " + str(e.value)
    assert "stale maps" in str(e.value)
    # Maps in hand go stale when the heights change under them.
    maps = relief.Maps.load(str(path), fbm)
    fbm.heights[0, 0] = 1.0 - fbm.heights[0, 0]
    with pytest.raises(ValueError, match="stale maps"):
        relief.trace(fbm, [[1, 1, 50]], [[0, 0, -1]], technique="cone", maps=maps)
    deeper = relief.Heightfield.generate("fbm", 48, 40, seed=3, depth=9.0)
    with pytest.raises(ValueError, match="depth"):
        maps.check(deeper)


def test_bake_refusals(fbm):
    with pytest.raises(ValueError, match="has no maps to bake"):
        relief.bake(fbm, "exact")
    with pytest.raises(ValueError, match="does not change the maps"):
        relief.bake(fbm, "cone", max_steps=5)
    with pytest.raises(ValueError, match="reads no maps"):
        relief.trace(fbm, [[1, 1, 50]], [[0, 0, -1]], technique="exact", maps=relief.bake(fbm, "cone"))
    with pytest.raises(ValueError, match="holds no maps for 'qdm'"):
        relief.trace(fbm, [[1, 1, 50]], [[0, 0, -1]], technique="qdm", maps=relief.bake(fbm, "cone"))
    with pytest.raises(OSError):
        relief.Maps.load("/nonexistent/maps.exr", fbm)
