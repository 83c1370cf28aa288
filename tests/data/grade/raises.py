"""A shade() that raises for every point."""


def shade(point, normal, eye, material, lights):
    return helper(point)


def helper(point):
    raise ValueError(f"cannot shade {point}")
