"""A shade() that returns RGBA, a single number or a string depending on the point."""


def shade(point, normal, eye, material, lights):
    if point[0] > 0:
        return [0.1, 0.2, 0.3, 1.0]
    if point[1] < 0:
        return "red"
    return 0.5
