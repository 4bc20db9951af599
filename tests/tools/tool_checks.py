"""Shared by the tests of tools/*.py: the repository's tools/ on the import path and a check() that
records failures instead of stopping at the first."""

import os
import sys

REPO_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO_DIR, "tools"))

FAILURES = []


def check(cond, what):
    print(("ok      " if cond else "FAILED  ") + what, flush=True)
    if not cond:
        FAILURES.append(what)


def exit_code():
    """1 (after saying how many) when a check failed, else 0."""
    if FAILURES:
        print("%d check(s) failed" % len(FAILURES))
        return 1
    print("all checks passed")
    return 0
