"""A file importing a module that does not exist."""

import not_a_real_module_for_phonglab  # noqa: F401


def shade(point, normal, eye, material, lights):
    return [0.0, 0.0, 0.0]
