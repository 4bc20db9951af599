#!/usr/bin/python3
"""tools/gap_restart.py: the gap is cut out of an .aevt file with the header rewritten and every other
record kept byte for byte; a file that is not .aevt is refused; the restart delay is read from the
segments of stats.json; and the command, with a stand-in for asynevo that reports a restart, writes the
table and gap_restart.json."""

import json
import os
import stat
import subprocess
import sys
import tempfile

import numpy as np

from tool_checks import REPO_DIR, check, exit_code

import gap_restart  # noqa: E402  (tools/, put on the path by tool_checks)


def write_aevt(path, times_ns):
    records = np.zeros(len(times_ns), dtype=gap_restart.AEVT_RECORD)
    records["t"] = times_ns
    records["x"] = np.arange(len(times_ns)) % 240
    records["y"] = 7
    records["p"] = np.where(np.arange(len(times_ns)) % 2 == 0, 1, -1)
    header = bytearray(64)
    header[0:8] = b"ASYNEVOE"
    header[8:12] = (1).to_bytes(4, "little")
    header[12:16] = (240).to_bytes(4, "little")
    header[16:20] = (180).to_bytes(4, "little")
    header[20:24] = (16).to_bytes(4, "little")
    header[24:32] = len(times_ns).to_bytes(8, "little")
    header[32:40] = int(times_ns[0]).to_bytes(8, "little", signed=True)
    header[40:48] = int(times_ns[-1]).to_bytes(8, "little", signed=True)
    with open(path, "wb") as f:
        f.write(bytes(header))
        records.tofile(f)


STAND_IN = """#!/usr/bin/python3
# Stands in for `asynevo run`: counts the events it is given and reports a restart 0.3 s after 1.4 s.
import json, os, sys
args = sys.argv[1:]
data, out = args[args.index("--dataset") + 1], args[args.index("--out") + 1]
count = int.from_bytes(open(os.path.join(data, "events.aevt"), "rb").read(64)[24:32], "little")
os.makedirs(out)
segments = [{"initialized_at_s": 0.2, "start_s": 0.0, "end_s": 0.95, "ended_by": "event_gap"},
            {"initialized_at_s": 1.7, "start_s": 1.4, "end_s": 1.95, "ended_by": "end_of_stream"}]
json.dump({"events": count, "estimator": {"segments": segments}}, open(os.path.join(out, "stats.json"), "w"))
"""


def main():
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "in.aevt")
        dst = os.path.join(tmp, "out.aevt")
        times = np.arange(10, dtype=np.int64) * 1_000_000  # 0 … 9 ms
        write_aevt(src, times)
        removed = gap_restart.cut_aevt(src, dst, 3_000_000, 6_000_000)
        check(removed == 3, f"three events of [3, 6) ms removed ({removed})")
        raw_in, raw_out = open(src, "rb").read(), open(dst, "rb").read()
        check(len(raw_out) == 64 + 16 * 7, f"the output holds 7 records ({len(raw_out)} bytes)")
        check(int.from_bytes(raw_out[24:32], "little") == 7, "the header's count is 7")
        check(int.from_bytes(raw_out[40:48], "little") == 9_000_000, "the header's last time is 9 ms")
        check(raw_out[:24] == raw_in[:24] and raw_out[48:64] == raw_in[48:64], "the rest of the header unchanged")
        check(raw_out[64:64 + 3 * 16] == raw_in[64:64 + 3 * 16], "the records before the gap byte for byte")
        check(raw_out[64 + 3 * 16:] == raw_in[64 + 6 * 16:], "the records after the gap byte for byte")

        bad = os.path.join(tmp, "bad.aevt")
        with open(bad, "wb") as f:
            f.write(b"NOTAEVT!" + bytes(56))
        try:
            gap_restart.cut_aevt(bad, dst, 0, 1)
            check(False, "a file that is not .aevt is refused")
        except ValueError as e:
            check("bad.aevt" in str(e), f"a file that is not .aevt is refused, naming it ({e})")

        stats = {"estimator": {"segments": [
            {"initialized_at_s": 0.3, "start_s": 0.0, "ended_by": "event_gap"},
            {"initialized_at_s": 5.75, "start_s": 5.25, "ended_by": "end_of_stream"}]}}
        delay, ended_by = gap_restart.restart_after(stats, 5.0, 5.4)
        check(abs(delay - 0.35) < 1e-12 and ended_by == "event_gap",
              f"restart 0.35 s after the gap, its first knot inside the gap ({delay}, {ended_by})")
        delay, ended_by = gap_restart.restart_after({"estimator": {"segments": stats["estimator"]["segments"][:1]}},
                                                    5.0, 5.4)
        check(delay is None and ended_by == "event_gap", "no segment after the gap: never restarted")

        # The command on a stand-in sequence (2 s of events every 1 ms) and a stand-in asynevo.
        seq = os.path.join(tmp, "seq-val")
        os.makedirs(seq)
        write_aevt(os.path.join(seq, "events.aevt"), np.arange(2000, dtype=np.int64) * 1_000_000)
        np.savetxt(os.path.join(seq, "groundtruth.txt"), np.c_[np.linspace(0.0, 1.999, 50), np.zeros((50, 7))])
        open(os.path.join(seq, "calib.txt"), "w").write("200 200 120 90 0 0 0 0 0\n")
        fake = os.path.join(tmp, "asynevo")
        open(fake, "w").write(STAND_IN)
        os.chmod(fake, os.stat(fake).st_mode | stat.S_IEXEC)
        out = os.path.join(tmp, "out")
        config = os.path.join(tmp, "config.yaml")
        open(config, "w").write("backend:\n  max_iterations: 5\n")
        proc = subprocess.run([sys.executable, os.path.join(REPO_DIR, "tools", "gap_restart.py"), "--asynevo", fake,
                               "--config", config, "--out", out, "--at", "1.0", "--gap-ms", "400", seq],
                              capture_output=True, text=True)
        check(proc.returncode == 0, f"the command succeeds ({proc.returncode}: {proc.stderr.strip()[-300:]})")
        result = json.load(open(os.path.join(out, "gap_restart.json")))
        run = result["runs"][0]
        check(run["events_removed"] == 400, f"400 events of [1.0, 1.4) s removed ({run['events_removed']})")
        check(abs(run["restart_s"] - 0.3) < 1e-9, f"restart 0.3 s after the gap ({run['restart_s']})")
        check(result["summary"]["within_target"] == 1, "within the 0.5 s target")
        check(os.path.exists(os.path.join(out, "seq-val", "sequence", "calib.txt")), "the sequence's files copied")
        check("seq-val" in proc.stdout and "0.300" in proc.stdout, "the table names the sequence and its delay")
        missing = subprocess.run([sys.executable, os.path.join(REPO_DIR, "tools", "gap_restart.py"), "--asynevo", fake,
                                  "--config", os.path.join(tmp, "none.yaml"), "--out", out, seq],
                                 capture_output=True, text=True)
        check(missing.returncode == 2 and "none.yaml" in missing.stderr,
              f"a missing configuration is named, exit 2 ({missing.returncode}: {missing.stderr.strip()[-120:]})")
    return exit_code()


if __name__ == "__main__":
    sys.exit(main())
