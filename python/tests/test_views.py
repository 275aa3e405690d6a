"""camera_rays are the rays render traces; techniques(); a user's own method against exact with
the bench's statistics (relief.compare)."""
import numpy as np
import pytest

import relief


def test_camera_rays_are_what_render_traces(fbm):
    view = dict(elevation=27.8, azimuth=60.0, size=(40, 30))
    origins, directions = relief.camera_rays(fbm, **view)
    assert origins.shape == directions.shape == (1200, 3)
    np.testing.assert_allclose(np.linalg.norm(directions, axis=1), 1.0, rtol=1e-6)
    image = relief.render(fbm, "cone", **view)
    hits = relief.trace(fbm, origins, directions, technique="cone")
    np.testing.assert_array_equal(image["hit"].ravel(), hits["hit"])
    # trace() normalizes directions again (as relief trace does a file's): t within an ulp or two.
    np.testing.assert_allclose(image["depth"].ravel(), hits["t"], rtol=1e-6)
    np.testing.assert_array_equal(image["steps"].ravel(), hits["steps"])
    assert image["color"].shape == (30, 40, 3) and image["color"].dtype == np.uint8
    assert image["stats"]["wrong"] == 0
    exact = relief.trace(fbm, origins, directions, technique="exact")
    stats = relief.compare(exact, hits)
    assert {k: v for k, v in stats.items() if k != "error"} == \
        {k: v for k, v in image["stats"].items() if k != "error"}
    assert stats["error"]["count"] == image["stats"]["error"]["count"]
    assert stats["error"]["max"] == pytest.approx(image["stats"]["error"]["max"], abs=1e-4)
    both = exact["hit"] & hits["hit"]
    np.testing.assert_allclose(image["error"].ravel()[both], np.abs(hits["t"][both] - exact["t"][both]),
                               atol=1e-4)


def test_techniques_rows():
    rows = {row["name"]: row for row in relief.techniques()}
    assert rows["exact"]["reference"] and rows["exact"]["contract"] == "exact"
    cone = rows["cone"]
    assert cone["has_maps"] and cone["paper"]
    for p in cone["parameters"]:
        assert p["min"] <= p["default"] <= p["max"] and p["help"] and p["role"]
    assert any(v["contract"] for row in rows.values() for v in row["variants"])


def fixed_step_march(hf, origins, directions, step=0.25, steps=400):
    """A user's technique in numpy: march in fixed steps, bilinear heights, first point below."""
    h = hf.heights.astype(np.float64) * hf.depth
    t = np.zeros(len(origins))
    hit = np.zeros(len(origins), bool)
    taken = np.zeros(len(origins), np.int32)
    for k in range(steps):
        p = origins + (k * step) * directions
        x = np.clip(p[:, 0] - 0.5, 0, hf.width - 1)
        y = np.clip(p[:, 1] - 0.5, 0, hf.height - 1)
        i, j = np.minimum(x.astype(int), hf.width - 2), np.minimum(y.astype(int), hf.height - 2)
        u, v = x - i, y - j
        z = (h[j, i] * (1 - u) * (1 - v) + h[j, i + 1] * u * (1 - v) + h[j + 1, i] * (1 - u) * v
             + h[j + 1, i + 1] * u * v)
        inside = (p[:, 0] >= 0) & (p[:, 0] <= hf.width) & (p[:, 1] >= 0) & (p[:, 1] <= hf.height)
        new = ~hit & inside & (p[:, 2] <= z)
        t[new] = k * step
        hit |= new
        taken[~hit] += 1
    t[~hit] = np.inf
    return {"hit": hit, "t": t.astype(np.float32), "steps": taken}


def test_user_technique_against_exact():
    hf = relief.Heightfield.generate("sine", 32, 32, depth=3.0)
    origins, directions = relief.camera_rays(hf, elevation=52.7, size=(32, 24), distance=0.6)
    # From just outside the box, so that the march starts where it can hit.
    exact = relief.trace(hf, origins, directions, technique="exact")
    ours = fixed_step_march(hf, origins.astype(np.float64), directions.astype(np.float64))
    stats = relief.compare(exact, ours)
    assert stats["rays"] == 32 * 24 and stats["hits"] > 100
    assert stats["wrong_rate"] < 0.05
    assert stats["error"]["mean"] < 0.5
    assert stats["steps"]["mean"] > exact["steps"].mean()
