"""A shade() that never returns (an endless loop)."""


def shade(point, normal, eye, material, lights):
    while True:
        pass
