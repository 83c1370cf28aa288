r"""The scenes and lessons the benchmarks and the tests run on, each written once.

Most of them are the *red sphere*: a unit sphere with a red-orange diffuse
colour ``kd = (0.8, 0.3, 0.2)``, a white highlight, an ambient light and a
point light at ``(2, 2.5, 3)``, up and to the right of the eye at
``(0, 0, 4)``. It comes

* as a :class:`~phonglab.scene.Scene`: :func:`red_sphere`;
* as the TOML tables of a scene file or a lesson's front matter:
  :func:`red_sphere_tables`, which :func:`lesson` wraps into a lesson's text
  (the benchmark's :func:`bench_lesson` is one).

:data:`LESSONS` are the lessons of the browser tests and the app's tests
(a sphere with controls, an experiment, a question; a spotlight on a floor; a
broken file; two common mistakes; the accuracy lesson); :func:`write_lessons`
puts them in a folder.

>>> red_sphere(24).material.kd
(0.8, 0.3, 0.2)
>>> sorted(LESSONS)[:2]
['01-sphere.md', '02-spot.md']
"""

from __future__ import annotations

from pathlib import Path

from phonglab import core
from phonglab.scene import Camera, Geometry, Scene

#: the red sphere's diffuse colour, specular coefficient, ambient coefficient and point light
KD = (0.8, 0.3, 0.2)
KS = 0.6
KA = 0.1
LIGHT_POSITION = (2.0, 2.5, 3.0)
AMBIENT = 0.2
#: the eye of every red sphere (also the default camera's)
EYE = (0.0, 0.0, 4.0)


def red_sphere(resolution: int | None = None, *, shininess: float = 40.0, lights=(), **fields) -> Scene:
    """The red sphere as a Scene.

    Parameters
    ----------
    resolution : int, optional
        Segments around the sphere (default: :class:`~phonglab.scene.Geometry`'s).
    shininess : float
        The specular exponent α.
    lights : sequence of core lights
        Lights added after the ambient and the point light.
    **fields
        Any other :class:`~phonglab.scene.Scene` field, replacing the red sphere's.
    """
    geometry = Geometry("sphere") if resolution is None else Geometry("sphere", resolution)
    scene = dict(
        geometry=geometry,
        material=core.Material(ka=KA, kd=KD, ks=KS, shininess=shininess),
        lights=(core.AmbientLight(intensity=AMBIENT), core.PointLight(position=LIGHT_POSITION)) + tuple(lights),
        camera=Camera(eye=EYE),
    )
    scene.update(fields)
    return Scene(**scene)


def _toml(value) -> str:
    """A number or a tuple of numbers as TOML (whole floats without their ``.0``)."""
    if isinstance(value, tuple):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return f"{value:g}"


def red_sphere_tables(resolution: int, *, ks: float = KS, shininess: float = 20, ambient: float = AMBIENT) -> str:
    """The red sphere as the TOML tables of a scene file or a lesson (geometry, material, lights, camera)."""
    return f"""\
[geometry]
kind = "sphere"
resolution = {resolution}

[material]
ka = {_toml(KA)}
kd = {_toml(KD)}
ks = {_toml(ks)}
shininess = {_toml(shininess)}

[[lights]]
type = "ambient"
intensity = {_toml(ambient)}

[[lights]]
type = "point"
position = {_toml(LIGHT_POSITION)}

[camera]
eye = {_toml(EYE)}
"""


def lesson(front: str, tables: str, body: str) -> str:
    """A lesson's text: the front matter's keys, then its tables, between ``+++`` lines, then the body."""
    return f"+++\n{front.strip()}\n\n{tables.strip()}\n+++\n\n{body.strip()}\n"


def bench_lesson(resolution: int) -> str:
    """The benchmark's lesson: the red sphere at ``resolution`` with a shininess slider."""
    return lesson(
        """
number = 1
title = "Benchmark sphere"
goal = "Move the shininess slider."
controls = ["material.shininess"]
""",
        red_sphere_tables(resolution, shininess=40),
        r"""
# Benchmark sphere

The shininess $\alpha$ sets the size of the highlight.
""",
    )


#: the test lessons: file name -> text
LESSONS = {
    "01-sphere.md": lesson(
        r"""
number = 1
title = "A red sphere"
goal = "Watch $k_s$ and $\\alpha$ shape the highlight."
controls = ["material.ks", "material.shininess", "lights[1].position", "interpolation"]
question = "Where is $n\\cdot l$ largest?"
answer = "Where the normal points at the light: $n = l$."
probe = [0.3, 0.4, 0.866]
""",
        red_sphere_tables(48)
        + """
[[experiments]]
label = "Matte"
text = "Set $k_s = 0$."
set = {"material.ks" = 0}
""",
        r"""
# A red sphere

The diffuse term is $k_d I_d \max(0, n\cdot l)$ and the specular one

$$k_s I_s \max(0, r\cdot v)^{\alpha}.$$

Costs \$0.
""",
    ),
    "02-spot.md": lesson(
        """
number = 2
title = "A spotlight on a floor"
goal = "Open and close the cone."
controls = ["lights[1].cutoff", "lights[1].exponent"]
""",
        """
[geometry]
kind = "plane"
resolution = 24

[material]
ka = 0.1
kd = 0.8
ks = 0.2
shininess = 10

[[lights]]
type = "ambient"
intensity = 0.1

[[lights]]
type = "spot"
position = [0, 0, 2]
direction = [0, 0, -1]
cutoff = 25
exponent = 4

[camera]
eye = [0, -3, 3]
up = [0, 0, 1]
""",
        r"""
# A spotlight on a floor

The spot factor is $\cos^e\theta$ inside the cone. With attenuation,

$$I = \frac{\cos^e\theta}{a + b\,d + c\,d^2} \left[k_d I_d \max(0, n\cdot l) + k_s I_s (r\cdot v)^{\alpha}\right],$$

and the light a point receives from the whole hemisphere is

$$L_o(\mathbf{x}, \omega_o) = L_e(\mathbf{x}, \omega_o) + \int_{\Omega} f_r(\mathbf{x}, \omega_i, \omega_o)\, L_i(\mathbf{x}, \omega_i)\, (\omega_i \cdot \mathbf{n})\, d\omega_i + \sum_{j=1}^{N} \frac{\Phi_j \cos\theta_j}{4\pi d_j^2}.$$

The cone's edge is at $\theta = $ cutoff.
""",
    ),
    "03-broken.md": lesson(
        """
number = 3
title = "A broken lesson"
controls = ["material.kd"]
""",
        """
[geometry]
kind = "sphere"

[material]
ka = 0.1
kd = -3
ks = 0.5
shininess = 40

[[lights]]
type = "point"
position = [2, 2, 2]
""",
        "# A broken lesson",
    ),
    "04-raw-normals.md": lesson(
        """
number = 4
title = "Normals left unnormalised"
controls = ["interpolation"]
mistake = "unnormalised-normals"
interpolation = "pixel"
""",
        red_sphere_tables(10, ks=0.8, shininess=60, ambient=0.15),
        """
# Normals left unnormalised

Per pixel, the blended normal must be normalised again.
""",
    ),
    "05-unclamped.md": lesson(
        """
number = 5
title = "Diffuse without the clamp"
controls = ["material.kd"]
mistake = "no-clamp-diffuse"
""",
        """
[geometry]
kind = "sphere"
resolution = 32

[material]
ka = 0.6
kd = 0.8
ks = 0
shininess = 10

[[lights]]
type = "ambient"
intensity = 0.3

[[lights]]
type = "point"
position = [-2.5, 2.0, 1.0]

[camera]
eye = [0, 0, 4]
""",
        r"""
# Diffuse without the clamp

Where $n\cdot l < 0$ the diffuse term must be zero, not negative.
""",
    ),
    "11-accuracy.md": lesson(
        """
number = 11
title = "Accuracy costs time"
controls = ["interpolation", "geometry.resolution", "material.shininess"]
interpolation = "gouraud"
""",
        red_sphere_tables(16, ks=0.8, shininess=200),
        """
# Accuracy costs time

Pick a method and a mesh; compare with the exact sphere.
""",
    ),
}


def write_lessons(folder, names=None) -> Path:
    """Write :data:`LESSONS` (or only those ``names``) into ``folder``; returns the folder."""
    folder = Path(folder)
    for name in names or LESSONS:
        (folder / name).write_text(LESSONS[name], encoding="utf-8")
    return folder
