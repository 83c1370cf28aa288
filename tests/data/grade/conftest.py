# The files here are student submissions for tests/test_grade.py, graded in a
# sandbox: pytest must not import them (some fail to load on purpose).
collect_ignore_glob = ["*.py"]
