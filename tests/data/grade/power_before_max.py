"""The textbook loop raising r·v to α before the max (mistake "power-before-max")."""

import math


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def unit(a):
    """a / |a|, and |a|; a zero vector stays zero."""
    length = math.sqrt(dot(a, a))
    if length == 0:
        return [0.0, 0.0, 0.0], 0.0
    return [a[0] / length, a[1] / length, a[2] / length], length


def shade(point, normal, eye, material, lights):
    p = [float(x) for x in point]
    n, _ = unit([float(x) for x in normal])
    v, _ = unit(sub([float(x) for x in eye], p))
    color = list(material.emission)
    for light in lights:
        kind = type(light).__name__
        if kind == "AmbientLight":
            for i in range(3):
                color[i] += material.ka[i] * light.ambient_rgb[i]
            continue
        if kind == "DirectionalLight":
            l, _ = unit(list(light.direction))
            f = 1.0
        else:
            l, d = unit(sub(list(light.position), p))
            a, b, c = light.attenuation
            f = 1.0 / (a + b * d + c * d * d)
            if kind == "SpotLight" and light.cutoff != 180:
                s, _ = unit(list(light.direction))
                cos_axis = -dot(l, s)
                if cos_axis >= math.cos(math.radians(light.cutoff)):
                    f *= max(0.0, cos_axis) ** light.exponent
                else:
                    f = 0.0
        nl = dot(n, l)
        diffuse = max(0.0, nl)
        specular = 0.0
        if nl > 0:
            r = [2 * nl * n[i] - l[i] for i in range(3)]
            rv = dot(r, v)
            specular = max(0.0, rv ** material.shininess)  # wrong: the power before the max
        for i in range(3):
            color[i] += f * (material.kd[i] * light.diffuse_rgb[i] * diffuse
                             + material.ks[i] * light.specular_rgb[i] * specular)
    return color
