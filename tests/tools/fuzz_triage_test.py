#!/usr/bin/python3
"""tools/fuzz_triage.py on sanitizer and libFuzzer reports in the shape they take (shortened from real
ones of the HDF5 harnesses): the frame to blame lies below the reporting machinery and the C runtime; a
fault there in libhdf5 that the guarded run survives is contained, anything else is a finding; and the
command, run on a stand-in harness, moves the contained artifacts and exits 1 on a finding."""

import os
import stat
import subprocess
import sys
import tempfile

from tool_checks import REPO_DIR, check, exit_code

import fuzz_triage  # noqa: E402  (tools/, put on the path by tool_checks)

H5 = "/lib/x86_64-linux-gnu/libhdf5_serial.so.103"
BIN = "/work/build-fuzz/bin/fuzz_dsec_events"

OVER_READ = f"""==1164==ERROR: AddressSanitizer: heap-buffer-overflow on address 0x611000000d94 at pc 0x5645
READ of size 1024 at 0x611000000d94 thread T0
    #0 0x564501a12943 in __interceptor_memcpy ({BIN}+0x167943) (BuildId: dc47)
    #1 0x7fb89d0c1fca in H5VM_memcpyvv ({H5}+0x2c1fca) (BuildId: e923)
    #2 0x7fb89ceb22b7  ({H5}+0xb22b7) (BuildId: e923)
    #3 0x564501b944f1 in asynevo::io_detail::readSlab(long, long, unsigned long, unsigned long, void*) /work/src/io/dsec_reader.cpp:112:10

0x611000000d94 is located 0 bytes to the right of 212-byte region
allocated by thread T0 here:
    #0 0x555db7c0453e in malloc ({BIN}+0x1d053e) (BuildId: dc47)
    #1 0x7fcf2d0ab736  ({H5}+0xab736) (BuildId: e923)
"""

LIBC_SEGV = f"""==6746==ERROR: AddressSanitizer: SEGV on unknown address 0x000000000000 (pc 0x7f928accf809 T0)
    #0 0x7f928accf809 in __memcpy_avx512_unaligned_erms string/../sysdeps/x86_64/multiarch/memmove-vec-unaligned-erms.S:273
    #1 0x564090938ab7 in __interceptor_memcpy ({BIN}+0x167ab7) (BuildId: dc47)
    #2 0x7f928b4f54de in H5F__accum_read ({H5}+0xf54de) (BuildId: e923)
"""

OUR_OVERFLOW = """==2002==ERROR: AddressSanitizer: stack-overflow on address 0x7ffe3b1f1ff8 (pc 0x55 T0)
    #0 0x55d1 in asynevo::readMvsecGroundTruth(std::string const&) /work/src/io/groundtruth_reader.cpp:55
    #1 0x55d2 in asynevo::readMvsecGroundTruth(std::string const&) /work/src/io/groundtruth_reader.cpp:57
"""

OOM_MALLOC = f"""==1234== ERROR: libFuzzer: out-of-memory (malloc(4294967067))
    #0 0x5638b0854621 in __sanitizer_print_stack_trace ({BIN}+0x1da621) (BuildId: dc47)
    #1 0x5638b07c6f78 in fuzzer::PrintStackTrace() ({BIN}+0x14cf78) (BuildId: dc47)
    #2 0x5638b07c9ae3 in __asan::asan_malloc(unsigned long, __sanitizer::BufferedStackTrace*) ({BIN}+0x14fae3)
    #3 0x5560fe2fe59d in malloc ({BIN}+0x1d059d) (BuildId: dc47)
    #4 0x7fbdd62ab736  ({H5}+0xab736) (BuildId: e923)
"""

frames = fuzz_triage.parse_frames(OVER_READ)
check(len(frames) == 4, "the first stack only: 4 frames, not the allocation's")
check(fuzz_triage.culprit(frames)[1] == "H5VM_memcpyvv", "the memcpy interceptor is passed over: H5VM_memcpyvv is to blame")
check(fuzz_triage.classify(OVER_READ, True) == ("contained", "heap-buffer-overflow in libhdf5 (H5VM_memcpyvv)"),
      "libhdf5's over-read, survived guarded: contained")
check(fuzz_triage.classify(OVER_READ, False)[0] == "finding", "the same, but the guarded run faulted: a finding")
check(fuzz_triage.culprit(fuzz_triage.parse_frames(LIBC_SEGV))[1] == "H5F__accum_read",
      "glibc's memcpy (by its source folder) and the interceptor are passed over")
check(fuzz_triage.classify(LIBC_SEGV, True)[0] == "contained", "a SEGV in libhdf5's read: contained")
verdict, why = fuzz_triage.classify(OUR_OVERFLOW, True)
check(verdict == "finding" and "groundtruth_reader.cpp:55" in why, "a fault in our reader is a finding, located: " + why)
verdict, why = fuzz_triage.classify(OOM_MALLOC, True)
check(verdict == "contained" and why.startswith("out-of-memory (malloc(4294967067))"),
      "libFuzzer's and ASan's frames are passed over for an allocation too large: " + why)
check(fuzz_triage.classify("INFO: Running with entropic power schedule\nExecuted x in 3 ms\n", True)[0] == "contained",
      "no fault in process and none guarded: contained")
check(fuzz_triage.classify("Executed x in 3 ms\n", False)[0] == "finding", "a fault only when guarded: a finding")

# The command on a stand-in harness that prints a report chosen by the artifact's name and the guard.
with tempfile.TemporaryDirectory() as tmp:
    reports = os.path.join(tmp, "reports")
    os.makedirs(reports)
    for name, text in (("libhdf5", OVER_READ), ("ours", OUR_OVERFLOW)):
        with open(os.path.join(reports, name), "w") as f:
            f.write(text)
    harness = os.path.join(tmp, "fuzz_stand_in")
    with open(harness, "w") as f:
        f.write(f"""#!/bin/sh
for a in "$@"; do f="$a"; done
case "$(basename "$f")" in crash-libhdf5*) r=libhdf5 ;; *) r=ours ;; esac
[ "$ASYNEVO_FUZZ_HDF5_UNGUARDED" = 1 ] || exit 0
cat "{reports}/$r"; exit 1
""")
    os.chmod(harness, os.stat(harness).st_mode | stat.S_IXUSR)
    findings = os.path.join(tmp, "findings")
    contained = os.path.join(tmp, "contained")
    os.makedirs(findings)
    for name in ("crash-libhdf5-1", "crash-ours-1", "oom-libhdf5-2", "README"):
        open(os.path.join(findings, name), "w").close()
    proc = subprocess.run([sys.executable, os.path.join(REPO_DIR, "tools", "fuzz_triage.py"), harness, findings,
                           "--move-contained", contained], stdout=subprocess.PIPE, text=True)
    check(proc.returncode == 1, "a finding: exit status 1")
    check("3 artifact(s): 1 contained, 2 finding(s)" in proc.stdout,
          "three artifacts sorted (oom-libhdf5-2 prints our report: not libhdf5's), README ignored: "
          + proc.stdout.strip().splitlines()[-1])
    check(os.listdir(contained) == ["crash-libhdf5-1"], "the contained artifact moved out of the findings")
    check(sorted(os.listdir(findings)) == ["README", "crash-ours-1", "oom-libhdf5-2"], "the finding stayed")

    # A replay that does not finish (a hang past libFuzzer's own watchdog, or a stopped process) is
    # killed at the time limit and counted as a finding; the sorting goes on.
    hanging = os.path.join(tmp, "fuzz_hangs")
    with open(hanging, "w") as f:
        f.write("#!/bin/sh\nexec sleep 30\n")
    os.chmod(hanging, os.stat(hanging).st_mode | stat.S_IXUSR)
    stuck = os.path.join(tmp, "stuck")
    os.makedirs(stuck)
    open(os.path.join(stuck, "timeout-1"), "w").close()
    proc = subprocess.run([sys.executable, os.path.join(REPO_DIR, "tools", "fuzz_triage.py"), hanging, stuck,
                           "--replay-timeout", "0.5"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    check(proc.returncode == 1 and "replay did not finish within 0.5 s" in proc.stdout
          and "1 artifact(s): 0 contained, 1 finding(s)" in proc.stdout,
          "a replay past the time limit: a finding, no traceback: " + proc.stdout.strip().splitlines()[-1])

sys.exit(exit_code())
