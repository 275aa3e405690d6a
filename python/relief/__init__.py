"""relief: ray casting of heightfields with a dozen published techniques (docs/python.md).

The compiled module (_relief) does the work through the C++ library; this file only re-exports it.
"""
from ._relief import (Heightfield, Maps, __version__, bake, camera_rays, compare, render,
                      techniques, trace)

__all__ = ["Heightfield", "Maps", "bake", "camera_rays", "compare", "render", "techniques",
           "trace", "__version__"]
