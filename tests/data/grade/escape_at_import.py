"""A file that reads /etc/passwd as it is imported: there is no /etc in the sandbox, so the file cannot be loaded."""

with open("/etc/passwd") as f:
    SECRET = f.read()


def shade(point, normal, eye, material, lights):
    return [0.0, 0.0, 0.0]
