"""Shared fixtures: the relief CLI of the same build (RELIEF_CLI, set by ctest) and small
heightfields. The module itself comes from PYTHONPATH (build/python)."""
import os
import shutil
import subprocess

import numpy as np
import pytest

import relief


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("RELIEF_CLI") or shutil.which("relief")
    if not path:
        pytest.skip("RELIEF_CLI is not set (ctest sets it to the build's relief)")
    return path


def run_cli(cli, *args):
    """relief ARGS...: (exit code, stdout, stderr)."""
    done = subprocess.run([cli, *map(str, args)], capture_output=True, text=True, timeout=600)
    return done.returncode, done.stdout, done.stderr


@pytest.fixture()
def fbm():
    return relief.Heightfield.generate("fbm", 48, 40, seed=3)


def write_rays_csv(path, origins, directions):
    """Rays as relief trace reads them; float32 values written exactly (9 significant digits)."""
    with open(path, "w") as f:
        f.write("ox,oy,oz,dx,dy,dz\n")
        for o, d in zip(origins.astype(np.float32), directions.astype(np.float32)):
            f.write(",".join(f"{float(v):.9g}" for v in (*o, *d)) + "\n")


def read_hits_csv(path):
    """relief trace's output: hit,t,x,y,z,steps per ray."""
    data = np.genfromtxt(path, delimiter=",", names=True)
    return np.atleast_1d(data)


def assert_same_hits(a, b):
    """Field by field: a structured comparison would count NaN points (misses) as different."""
    assert a.dtype.names == b.dtype.names
    for name in a.dtype.names:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)
