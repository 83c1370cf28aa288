"""A file that defines shading under another name."""


def shade_point(point, normal, eye, material, lights):
    return [0.0, 0.0, 0.0]
