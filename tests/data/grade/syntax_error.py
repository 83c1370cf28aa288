"""A file with a syntax error on line 5."""


def shade(point, normal, eye, material, lights)
    return [0, 0, 0]
