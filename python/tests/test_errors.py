"""Bad input raises the exception of its kind with the CLI's message, never a crash."""
import numpy as np
import pytest

import relief
from conftest import run_cli

UP = np.array([[1.0, 1.0, 50.0]])
DOWN = np.array([[0.0, 0.0, -1.0]])


def cli_error(cli, *args):
    code, _, err = run_cli(cli, *args)
    assert err.startswith("relief: error: "), err
    return code, err[len("relief: error: "):].strip()


def test_io_errors_are_oserror(cli, tmp_path):
    missing = tmp_path / "missing.png"
    with pytest.raises(OSError) as e:
        relief.Heightfield.load(str(missing))
    code, message = cli_error(cli, "info", missing)
    assert code == 2 and e.value.exit_code == 2 and str(e.value) == message


def test_bad_arguments_are_valueerror(cli, fbm):
    with pytest.raises(ValueError) as e:
        relief.trace(fbm, UP, DOWN, technique="nope")
    code, message = cli_error(cli, "trace", "gen:fbm:48x40:3", "-t", "nope", "--rays", "-")
    assert code == 1 and e.value.exit_code == 1 and str(e.value) == message
    with pytest.raises(ValueError) as e:
        relief.trace(fbm, UP, DOWN, technique="cone", cone_max=-5)
    assert "cone-max" in str(e.value)
    code, message = cli_error(cli, "trace", "gen:fbm:48x40:3", "-t", "cone", "--param", "cone-max=-5",
                              "--rays", "-")
    assert str(e.value) == message
    with pytest.raises(ValueError) as e:
        relief.Heightfield.generate("nope", 8, 8)
    code, message = cli_error(cli, "info", "gen:nope:8x8")
    assert str(e.value) == message
    with pytest.raises(ValueError):
        relief.Heightfield.load("gen:fbm:8x8", edge="mirror")
    with pytest.raises(ValueError):
        relief.trace(fbm, UP, DOWN, backend="vulkan")
    with pytest.raises(ValueError):
        relief.trace(fbm, UP, DOWN, threads=-1)
    with pytest.raises(ValueError):
        relief.trace(fbm, UP, DOWN, technique="linear", max_steps="many")
    with pytest.raises(ValueError, match="given twice"):
        relief.trace(fbm, UP, DOWN, technique="linear", max_steps=3, **{"max-steps": 4})
    with pytest.raises(ValueError, match="expected a number"):
        relief.trace(fbm, UP, DOWN, technique="linear", max_steps=np.array([1, 2]))
    with pytest.raises(ValueError, match="crop: expected four integers"):
        relief.Heightfield.load("gen:fbm:8x8", crop="abc")
    with pytest.raises(ValueError, match="maps: expected relief.Maps"):
        relief.trace(fbm, UP, DOWN, maps="maps.exr")
    with pytest.raises(ValueError, match="own method"):
        relief.render(fbm, "curves", size=(8, 8))
    with pytest.raises(TypeError):
        relief.Heightfield.load("gen:fbm:8x8", depht=3)


def test_bad_hit_sets(fbm):
    good = relief.trace(fbm, UP, DOWN, technique="exact")
    for bad in [{"hit": [1], "t": [np.inf], "steps": [0]},        # a hit without a distance
                {"hit": [1, 0], "t": [1.0], "steps": [0, 0]},     # lengths differ
                {"hit": [1], "t": [1.0]},                         # no steps
                [1, 2, 3], None]:
        with pytest.raises(ValueError):
            relief.compare(good, bad)
    assert relief.compare(good, {"hit": good["hit"], "t": good["t"], "steps": good["steps"]})["wrong"] == 0


def test_bad_ray_arrays(fbm, cli, tmp_path):
    for origins, directions in [(np.zeros((3, 2)), np.zeros((3, 2))),  # wrong shape
                                (np.zeros(3), np.zeros(3)),            # 1-D
                                (np.zeros((3, 3)), np.zeros((4, 3))),  # row counts differ
                                ([["a", "b", "c"]], DOWN)]:            # not numbers
        with pytest.raises(ValueError):
            relief.trace(fbm, origins, directions)
    rays = np.repeat(DOWN, 4, axis=0)
    zero = rays.copy()
    zero[2] = 0.0
    with pytest.raises(ValueError, match="row 2 of origins/directions: zero or unusable direction"):
        relief.trace(fbm, np.repeat(UP, 4, axis=0), zero)
    nan = np.repeat(UP, 4, axis=0)
    nan[3, 1] = np.nan
    with pytest.raises(ValueError, match="row 3 of origins/directions: non-finite value in ray"):
        relief.trace(fbm, nan, rays)
    # The CLI's words for the same rays in a file.
    (tmp_path / "rays.csv").write_text("1,1,50,0,0,0\n")
    code, message = cli_error(cli, "trace", "gen:fbm:48x40:3", "--rays", tmp_path / "rays.csv")
    assert code == 3 and message.endswith("zero or unusable direction")
    with pytest.raises(ValueError, match="t_max"):
        relief.trace(fbm, UP, DOWN, t_max=np.nan)
    with pytest.raises(ValueError, match="t_max"):
        relief.trace(fbm, UP, DOWN, t_max=[1.0, 2.0])


def test_bad_heights(fbm):
    fbm.heights[3, 4] = np.nan
    with pytest.raises(ValueError, match=r"heights\[3, 4\]"):
        relief.trace(fbm, UP, DOWN)
    fbm.heights[3, 4] = 2.0
    with pytest.raises(ValueError, match=r"in \[0, 1\]"):
        relief.bake(fbm, "cone")
    with pytest.raises(ValueError):
        relief.Heightfield.from_array(np.full((4, 4), 3.0))
    with pytest.raises(ValueError):
        relief.Heightfield.from_array(np.zeros((2, 2, 2)))
    with pytest.raises(ValueError):
        relief.Heightfield.from_array(np.zeros((0, 4)))


def test_bad_views(fbm):
    with pytest.raises(ValueError, match="elevation"):
        relief.camera_rays(fbm, elevation=100)
    with pytest.raises(ValueError, match="fov"):
        relief.camera_rays(fbm, fov=float("nan"))
    with pytest.raises(ValueError, match="width"):
        relief.camera_rays(fbm, size=(0, 10))
    with pytest.raises(ValueError, match="light_azimuth"):
        relief.render(fbm, size=(8, 8), light_azimuth=1000)
