#!/usr/bin/python3
"""Sorts what an HDF5 harness's unguarded fuzzing run left in its findings folder (docs/reliability.md).

scripts/fuzz.sh runs the HDF5 harnesses with libhdf5 in the fuzzer's own process
(ASYNEVO_FUZZ_HDF5_UNGUARDED=1) and lets libFuzzer go on past crashes, memory exhaustion and
timeouts: libhdf5 1.10 crashes on many corrupt files, which every run contains by parsing the file in
a child process first (src/io/hdf5_isolation.hpp). Each artifact is sorted here:

- its report is reproduced in process, and the frame where it happened (the first below the
  sanitizer's, libFuzzer's and the C/C++ runtime's own frames) names the library at fault;
- it is then run as every run meets it, guarded by the child process, which must end without a fault.

An artifact is contained when the guarded run ends cleanly and either libhdf5 or one of its filter
libraries is at fault, or the fault does not reproduce in process (an out-of-memory that took a whole
job's leaks, or an input a reader now rejects before libhdf5 reads it); anything else is a finding.
Exit status 1 when there is a finding.

Usage: fuzz_triage.py HARNESS_BINARY FINDINGS_DIR [--move-contained DIR]
"""

import argparse
import os
import re
import shutil
import subprocess
import sys

# "#3 0x7f.. in H5Dread (/lib/x86_64-linux-gnu/libhdf5_serial.so.103+0xc7f74)",
# "#8 0x56.. in asynevo::...::readSlab(...) /work/main/src/io/dsec_reader.cpp:112:10",
# "#2 0x7f..  (/lib/x86_64-linux-gnu/libhdf5_serial.so.103+0xb22b7)" (a symbol-less frame).
FRAME = re.compile(r"^\s*#(\d+) 0x[0-9a-f]+ (?:in (.*?) )?\s*"
                   r"(\((?P<module>[^()]*?)\+0x[0-9a-f]+\)|(?P<file>\S+:\d+(?::\d+)?))")

# Frames of the machinery that reports a fault, not of the code that caused it.
MACHINERY_FUNCTIONS = re.compile(
    r"^(__sanitizer|__asan|__lsan|__ubsan|__interceptor_|___interceptor_|__sanitizer_|fuzzer::|"
    r"malloc|calloc|realloc|free|operator new|operator delete|posix_memalign|aligned_alloc|"
    r"__libc_|abort|raise|gsignal|__pthread_kill|__mem|__str|__wmem)")
# The C runtime's own frames, by library or (when it has line tables) by glibc's source folders.
MACHINERY_MODULES = re.compile(r"/(libc\.so|libstdc\+\+\.so|libgcc_s\.so|libm\.so|ld-linux)|"
                               r"^(string|sysdeps)/")
# libhdf5 and the filter plugins and compression libraries it loads for a file.
HDF5_MODULES = re.compile(r"/(libhdf5[^/]*\.so|libH5Z[^/]*\.so|libh5[^/]*\.so|libblosc[^/]*\.so|"
                          r"libblosc_filter\.so|liblz4\.so|libbz2\.so|libz\.so|libzstd\.so|libsz\.so|"
                          r"libaec\.so)")


def parse_frames(report):
    """The frames of a report's first stack: (number, function or '', module path or source file)."""
    frames = []
    for line in report.splitlines():
        m = FRAME.match(line)
        if not m:
            if frames and not line.strip():
                break  # the end of the first stack
            continue
        number = int(m.group(1))
        if frames and number == 0:
            break  # a second stack (where the memory was allocated)
        frames.append((number, m.group(2) or "", m.group("module") or m.group("file") or ""))
    return frames


def culprit(frames):
    """The first frame below the reporting machinery, or None when every frame is machinery."""
    for frame in frames:
        _, function, where = frame
        if MACHINERY_FUNCTIONS.match(function) or MACHINERY_MODULES.search(where):
            continue
        return frame
    return None


def kind_of(report):
    """The fault a report describes, in a few words."""
    for pattern in (r"ERROR: AddressSanitizer: ([\w-]+)", r"ERROR: LeakSanitizer: (detected memory leaks)",
                    r"ERROR: libFuzzer: (out-of-memory \((?:[^()]|\([^()]*\))*\))",
                    r"ERROR: libFuzzer: (timeout)", r"ERROR: (replay did not finish within [\d.]+ s)",
                    r"(runtime error: [^\n]*)", r"ERROR: libFuzzer: ([\w-]+)"):
        m = re.search(pattern, report)
        if m:
            return m.group(1)
    return "no fault reproduced"


def classify(report, guarded_ok):
    """('contained' | 'finding', why) for an artifact's in-process report and its guarded run."""
    kind = kind_of(report)
    if kind == "no fault reproduced":
        return ("finding" if not guarded_ok else "contained",
                "does not reproduce in process" + ("" if guarded_ok else "; the guarded run faulted"))
    frame = culprit(parse_frames(report))
    if frame is None:
        return "finding", f"{kind} with no frame to blame"
    at = frame[1] or os.path.basename(frame[2])
    if not HDF5_MODULES.search(frame[2]):
        return "finding", f"{kind} in {at} ({frame[2]})"
    if not guarded_ok:
        return "finding", f"{kind} in libhdf5 ({at}), and the guarded run faulted too"
    return "contained", f"{kind} in libhdf5 ({at})"


REPLAY_TIMEOUT_S = 600  # libFuzzer's own -timeout=20 ends a hang in the harness far sooner


def run(binary, artifact, unguarded, timeout_s=None):
    """(exit status, output) of one replay; a replay still running after the time limit is killed and
    reported as such (exit status None), which the sorting counts as a finding."""
    env = dict(os.environ)
    env["ASYNEVO_FUZZ_HDF5_UNGUARDED"] = "1" if unguarded else "0"
    limit = REPLAY_TIMEOUT_S if timeout_s is None else timeout_s
    try:
        proc = subprocess.run([binary, "-rss_limit_mb=2048", "-timeout=20", artifact], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, errors="replace",
                              timeout=limit)
    except subprocess.TimeoutExpired:
        return None, f"ERROR: replay did not finish within {limit:g} s\n"
    return proc.returncode, proc.stdout


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("binary")
    ap.add_argument("findings")
    ap.add_argument("--move-contained", metavar="DIR",
                    help="move the contained artifacts here (out of the findings folder)")
    ap.add_argument("--replay-timeout", type=float, default=REPLAY_TIMEOUT_S, metavar="S",
                    help="kill a replay after this many seconds and count the artifact as a finding")
    args = ap.parse_args(argv)
    artifacts = sorted(f for f in os.listdir(args.findings)
                       if re.match(r"(crash|oom|timeout|leak|slow-unit)-", f))
    findings = 0
    for name in artifacts:
        path = os.path.join(args.findings, name)
        _, report = run(args.binary, path, unguarded=True, timeout_s=args.replay_timeout)
        guarded_code, guarded_report = run(args.binary, path, unguarded=False, timeout_s=args.replay_timeout)
        verdict, why = classify(report, guarded_code == 0)
        print(f"{verdict:9s} {name}: {why}")
        if verdict == "finding":
            findings += 1
            if guarded_code != 0:
                print("  guarded run: " + kind_of(guarded_report))
        elif args.move_contained:
            os.makedirs(args.move_contained, exist_ok=True)
            shutil.move(path, os.path.join(args.move_contained, name))
    print(f"{len(artifacts)} artifact(s): {len(artifacts) - findings} contained, {findings} finding(s)")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
