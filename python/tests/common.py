"""Shared paths of the Python module's tests (set by python/CMakeLists.txt for ctest)."""
import decimal
import os
import pathlib

SOURCE_DIR = pathlib.Path(os.environ.get("ASYNEVO_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
DATA = SOURCE_DIR / "tests" / "data"
WORK = pathlib.Path(os.environ.get("ASYNEVO_TEST_WORK", "/tmp/asynevo-python-tests"))
# The 3 s boxes/6dof sequence the ctest fixture python.simulate_fixture writes.
SIM = WORK / "sim_boxes"


def ecd_text_events(path, limit=None):
    """Events of an ECD events.txt parsed here, independently of the C++ reader: decimal seconds rounded
    to the nearest ns (docs/architecture.md: text timestamps are converted exactly, rounding at the ns)."""
    rows = []
    with open(path) as f:
        for line in f:
            if limit is not None and len(rows) >= limit:
                break
            ts, x, y, p = line.split()
            t_ns = int((decimal.Decimal(ts) * 10**9).to_integral_value(rounding=decimal.ROUND_HALF_EVEN))
            rows.append((t_ns, int(x), int(y), 1 if int(p) == 1 else -1))
    return rows
