#!/usr/bin/python3
"""Unit tests of tools/config_text.py: overrides and backend-section swaps of configuration text (used
by the evaluation matrix's replays; registered with ctest in tests/tools/CMakeLists.txt)."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tool_checks import check, exit_code  # noqa: E402

import config_text as rs  # noqa: E402


def raises_exit(fn):
    try:
        fn()
    except SystemExit as e:
        return str(e)
    return None


def main():
    text = "frontend:\n  min_dt_ms: 5\n  tracker: x\nbackend:\n  q_c: [10, 10, 10, 1, 1, 1]\n  min_dt_ms: 7\n"
    out = rs.override_yaml(text, ["backend.q_c=[10,10,10,0.3,0.3,0.3]", "frontend.min_dt_ms=4"], "cfg")
    check("  q_c: [10,10,10,0.3,0.3,0.3]" in out, "a backend list is replaced")
    check("frontend:\n  min_dt_ms: 4\n" in out and "  min_dt_ms: 7" in out,
          "a key is replaced in its own section only: %r" % out)
    msg = raises_exit(lambda: rs.override_yaml(text, ["backend.nope=1"], "cfg.yaml"))
    check(msg is not None and "no key nope in section backend of cfg.yaml" in msg, "an unknown key is an error: %s" % msg)
    msg = raises_exit(lambda: rs.override_yaml(text, ["q_c=1"], "cfg.yaml"))
    check(msg is not None and "section.key=value" in msg, "a malformed override is an error: %s" % msg)
    check(rs.override_yaml(text, [], "cfg") == text, "no override leaves the text as it was")
    recorded = "# run\nsensor:\n  width: 240\nbackend:\n  q_c: [1]\n  knot_dt_ms: 50\nframes:\n  n: 2\n"
    base = "frontend:\n  min_dt_ms: 5\nbackend:\n  # new\n  q_c: [9]\n"
    merged = rs.with_backend_of(recorded, base)
    check(merged == "# run\nsensor:\n  width: 240\nbackend:\n  # new\n  q_c: [9]\nframes:\n  n: 2\n",
          "the backend section is taken from the base, the rest from the recording: %r" % merged)
    check(rs.without_backend(recorded) == rs.without_backend(merged), "the tracks' key ignores the backend section")
    check(rs.without_backend(recorded) != rs.without_backend(recorded.replace("240", "346")),
          "the tracks' key follows every other section")
    msg = raises_exit(lambda: rs.with_backend_of("sensor:\n  width: 1\n", base))
    check(msg is not None and "no section backend" in msg, "a configuration without a backend section is an error")
    return exit_code()


if __name__ == "__main__":
    sys.exit(main())
