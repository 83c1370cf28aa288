"""The record of the reference kernel: what it used, and formulas that give back its terms.

``shade_reference(..., trace=True)`` returns the record beside the shading.
Every model of the core and every common mistake of the catalogue is walked
(a model or mistake added later is walked too): the shading is the one
without the record, bit for bit; each term's formula, evaluated from the
recorded values, gives back the recorded term; the terms add up to the
colour; and a mistake's record holds its own intermediate values (the
unnormalised light's ``n·l`` is ``d cos θ``). A failure prints the inputs.
"""

from __future__ import annotations

import numpy as np
import pytest

import phonglab as pl
from phonglab.core.record import evaluate, names_in, resolve
from phonglab.teaching import MISTAKES

MATERIAL = pl.Material(ka=(0.1, 0.2, 0.3), kd=(0.8, 0.3, 0.2), ks=0.6, shininess=12, emission=(0.01, 0.0, 0.02))
LIGHTS = (
    pl.AmbientLight(intensity=0.2),
    pl.PointLight(position=(2.0, 2.5, 3.0), attenuation=(1.0, 0.2, 0.05)),
    pl.DirectionalLight(direction=(-1.0, 0.5, 0.3), color=(0.2, 0.4, 1.0)),
    pl.SpotLight(position=(0.0, 0.0, 3.0), direction=(0.0, 0.0, -1.0), cutoff=40, exponent=3),
    pl.AmbientLight(color=(1.0, 0.5, 0.0), intensity=0.1),
)
EYE = (0.5, -0.3, 4.0)


def sphere_points(count=400, seed=3):
    """Points on a unit sphere (both sides of every light) with slightly too short normals."""
    rng = np.random.default_rng(seed)
    n = rng.normal(size=(count, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return n.copy(), n * 0.9


def shade_variants():
    """(name, shade function): the reference kernel and every mistake of the catalogue."""
    return [("correct", pl.shade_reference)] + [(name, m.shade) for name, m in MISTAKES.items()]


@pytest.mark.parametrize("model", pl.MODELS)
@pytest.mark.parametrize("name, shade", shade_variants(), ids=[n for n, _ in shade_variants()])
def test_every_term_is_its_formula_of_the_recorded_values(model, name, shade):
    points, normals = sphere_points()
    args = dict(material=MATERIAL, lights=LIGHTS, eye=EYE, model=model, two_sided=True)
    with np.errstate(over="ignore", invalid="ignore"):
        plain = shade(points, normals, **args)
        shading, record = shade(points, normals, trace=True, **args)
    inputs = f"{name}, {model}"
    for term in ("ambient", "diffuse", "specular", "emission", "color"):
        assert np.array_equal(getattr(plain, term), getattr(shading, term), equal_nan=True), (inputs, term)
    assert record.model == model
    assert [lr.index for lr in record.lights] == [1, 2, 3], (inputs, [lr.index for lr in record.lights])
    assert [lr.kind for lr in record.lights] == ["point", "directional", "spot"]

    def close(got, want, what):
        ok = np.isclose(got, want, rtol=1e-12, atol=1e-15) | (np.isnan(got) & np.isnan(want))
        ok |= np.isinf(want) & (got == want)
        bad = np.argwhere(~ok)
        assert not bad.size, f"{inputs}: {what} at {bad[:3].tolist()}: {np.asarray(got)[tuple(bad[0])]} " \
                             f"!= {np.asarray(want)[tuple(bad[0])]}"

    for lr in record.lights:
        for term in ("diffuse", "specular"):
            formula = lr.terms[term]
            got = evaluate(formula, lambda key, lr=lr: record.lookup(key, lr))
            close(np.broadcast_to(got, lr[term].shape), lr[term], f"light {lr.index} {term} = {formula}")
        close(lr["adds"], lr["diffuse"] + lr["specular"], f"light {lr.index} adds")
    close(np.broadcast_to(evaluate(record.terms["ambient"], record.lookup), shading.ambient.shape),
          shading.ambient, f"ambient = {record.terms['ambient']}")
    # the terms add up to the colour and to the shading's terms
    close(sum(lr["diffuse"] for lr in record.lights), shading.diffuse, "Σ diffuse")
    close(sum(lr["specular"] for lr in record.lights), shading.specular, "Σ specular")
    total = record["ambient"] + record["emission"] + sum(lr["adds"] for lr in record.lights)
    assert np.allclose(total, shading.color, rtol=1e-12, atol=1e-14, equal_nan=True), inputs


def test_the_records_vectors_are_the_models():
    points, normals = sphere_points(50)
    _, record = pl.shade_reference(points, normals, material=MATERIAL, lights=LIGHTS, eye=EYE, trace=True)
    point = record.light(1)
    n = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    l = (np.array(LIGHTS[1].position) - points) / np.linalg.norm(np.array(LIGHTS[1].position) - points, axis=1,
                                                                    keepdims=True)
    v = (np.array(EYE) - points) / np.linalg.norm(np.array(EYE) - points, axis=1, keepdims=True)
    r = 2 * np.sum(n * l, axis=1, keepdims=True) * n - l
    h = (l + v) / np.linalg.norm(l + v, axis=1, keepdims=True)
    for name, want in (("l", l), ("r", r), ("h", h)):
        np.testing.assert_allclose(point[name], want, atol=1e-14, err_msg=name)
    np.testing.assert_allclose(record["n"], n, atol=1e-15)
    np.testing.assert_allclose(record["v"], v, atol=1e-15)
    np.testing.assert_allclose(point["n·l"], np.sum(n * l, axis=1), atol=1e-14)
    np.testing.assert_allclose(point["r·v"], np.sum(r * v, axis=1), atol=1e-14)
    np.testing.assert_allclose(point["n·h"], np.sum(n * h, axis=1), atol=1e-14)
    d = np.linalg.norm(np.array(LIGHTS[1].position) - points, axis=1)
    np.testing.assert_allclose(point["attenuation"], 1 / (1 + 0.2 * d + 0.05 * d * d), rtol=1e-14)
    np.testing.assert_allclose(point["diffuse weight"], np.maximum(0, np.sum(n * l, axis=1)), atol=1e-15)


def test_a_mistakes_record_holds_its_own_wrong_values():
    # the unnormalised light: l = position − p, so n·l is d cos θ, and the diffuse term follows it
    point, normal = np.array([[0.0, 0.0, 1.0]]), np.array([[0.0, 0.0, 1.0]])
    lamp = pl.PointLight(position=(0.0, 0.0, 4.0))
    args = dict(material=MATERIAL, lights=[lamp], eye=EYE)
    _, right = pl.shade_reference(point, normal, trace=True, **args)
    _, wrong = MISTAKES["unnormalised-light"].shade(point, normal, trace=True, **args)
    assert right.light(0)["n·l"][0] == pytest.approx(1.0)
    assert wrong.light(0)["n·l"][0] == pytest.approx(3.0), wrong.light(0).values
    assert wrong.light(0)["diffuse"][0] == pytest.approx(3.0 * np.asarray(MATERIAL.kd))
    # a swapped weight shows its own formula; the unclamped diffuse is n·l itself
    _, unclamped = MISTAKES["no-clamp-diffuse"].shade(point, normal, trace=True, **args)
    assert unclamped.light(0).terms["diffuse"] == ("mul", "f", "k_d", "I_d", "n·l")
    assert right.light(0).terms["diffuse"] == ("mul", "f", "k_d", "I_d", ("max0", "n·l"))
    # the attenuated ambient reads the lamp's f; with no lamp it has none to read and shows the value
    _, attenuated = MISTAKES["attenuated-ambient"].shade(point, normal, trace=True, **args)
    assert "f_lamp" in names_in(attenuated.terms["ambient"])
    _, alone = MISTAKES["attenuated-ambient"].shade(point, normal, trace=True, material=MATERIAL,
                                                     lights=[pl.AmbientLight()], eye=EYE)
    assert alone.terms["ambient"] == "ambient"


def test_a_closed_gate_resolves_to_zero():
    formula = ("mul", "f", ("if", ("n·l", "r·v"), ("pow", ("max0", "r·v"), "α")))
    values = {"f": 1.0, "n·l": -0.2, "r·v": 0.9, "α": 10.0}
    assert resolve(formula, values.get) == ("mul", "f", 0)
    values["n·l"] = 0.3
    assert resolve(formula, values.get) == ("mul", "f", ("pow", ("max0", "r·v"), "α"))
    assert evaluate(formula, values.get) == pytest.approx(0.9 ** 10)


def test_ambient_intensity_is_the_one_both_kernels_and_the_planner_use():
    points, normals = sphere_points(5)
    ka_ia = np.asarray(MATERIAL.ka) * pl.ambient_intensity(LIGHTS)
    fast = pl.shade(points, normals, material=MATERIAL, lights=LIGHTS, eye=EYE)
    ref = pl.shade_reference(points, normals, material=MATERIAL, lights=LIGHTS, eye=EYE)
    assert np.array_equal(fast.ambient[0], ka_ia) and np.array_equal(ref.ambient[0], ka_ia), (fast.ambient[0], ka_ia)
    plan = pl.plan_effects(MATERIAL, LIGHTS, eye=EYE)
    assert f"({ka_ia[0]:.3g}, {ka_ia[1]:.3g}, {ka_ia[2]:.3g})" in dict(plan.computed)["ambient"], plan.computed


def test_the_planners_reasons_write_three_significant_digits_as_the_readout_does():
    # the plan panel showed (0.0604857, 0.181457, 0.2117) beside the readout's three digits
    material = pl.Material(ka=(0.0604857, 0.181457, 0.2117), kd=0.5, ks=0.0, shininess=10)
    plan = pl.plan_effects(material, (pl.AmbientLight(intensity=1.0), pl.PointLight(position=(1, 2, 3))), eye=EYE)
    reason = dict(plan.computed)["ambient"]
    assert "(0.0605, 0.181, 0.212)" in reason, reason


def test_vectors_come_from_the_record():
    light = LIGHTS[3]
    pv = pl.vectors((0.2, 0.1, 0.9), (0.1, 0.0, 1.0), light=light, eye=EYE)
    _, record = pl.shade_reference([[0.2, 0.1, 0.9]], [[0.1, 0.0, 1.0]], material=MATERIAL, lights=[light],
                                   eye=EYE, trace=True)
    lr = record.at(0).light(0)
    assert pv.nl == lr["n·l"] and pv.rv == lr["r·v"] and pv.nh == lr["n·h"], (pv, lr.values)
    assert pv.spot == lr["spot"] and pv.attenuation == lr["attenuation"] and pv.distance == lr["d"]
