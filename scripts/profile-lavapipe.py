#!/usr/bin/env python3
"""Where lavapipe's compiled kernels spend their time.

lavapipe compiles each kernel to machine code at run time, so `perf report`
shows its samples only as addresses in anonymous memory. This script runs a
wavepath command, samples it with `perf record` while it runs, copies the
sampled code out of the live process (/proc/PID/mem), disassembles it with
`objdump`, and splits it into functions at their returns: the kernels' bodies
and the helper routines lavapipe calls from them (a texel fetch is one). It
prints each function's share of the samples and the hottest instructions,
and writes the disassembly annotated with sample counts.

Usage (the command must still be running when the sampling ends):
  scripts/profile-lavapipe.py --out DIR [--delay S] [--seconds S] -- \\
      build/wavepath bench --raycast --scenes scenes/dragon.json --repeats 40

Needs perf (Debian: linux-perf), objdump (binutils) and the right to read
another process's memory (root, or ptrace allowed). Set LP_NUM_THREADS=1 and
run under `taskset -c 0` for a profile of one core.
"""
import argparse
import collections
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time


def sampled_ips(perf_data):
    """Sample counts by instruction address, for samples outside any file (JIT code)."""
    out = subprocess.run(["perf", "script", "-i", perf_data, "-F", "ip,dso"], capture_output=True, text=True,
                         check=True).stdout
    counts = collections.Counter()
    for line in out.splitlines():
        fields = line.split()
        if len(fields) < 2:
            continue
        dso = " ".join(fields[1:]).strip("()")
        # JIT code has no file behind it: perf names it after the perf map
        # it would read (/tmp/perf-PID.map), [JIT] or [unknown].
        if re.search(r"perf-\d+\.map$", dso) or dso.startswith("[JIT]") or dso == "[unknown]":
            counts[int(fields[0], 16)] += 1
    return counts


def anonymous_mappings(pid):
    """(start, end) of the process's executable mappings not backed by a file."""
    maps = []
    with open(f"/proc/{pid}/maps") as f:
        for line in f:
            fields = line.split()
            lo, hi = (int(x, 16) for x in fields[0].split("-"))
            path = fields[5] if len(fields) > 5 else ""
            if "x" in fields[1] and not path.startswith("/") and not path.startswith("["):
                maps.append((lo, hi))
    return maps


def disassemble(code, start):
    """[(address, text)] of the instructions in the bytes `code` loaded at `start`."""
    with tempfile.NamedTemporaryFile(suffix=".bin") as f:
        f.write(code)
        f.flush()
        out = subprocess.run(["objdump", "-D", "-b", "binary", "-m", "i386:x86-64", f"--adjust-vma={start:#x}", f.name],
                             capture_output=True, text=True, check=True).stdout
    rows = []
    for line in out.splitlines():
        m = re.match(r"\s*([0-9a-f]+):\t(?:[0-9a-f]{2} )+\s*\t?(.*)", line)
        # A long instruction's last bytes come on a line of their own, without text.
        if m and m.group(2).strip():
            rows.append((int(m.group(1), 16), m.group(2).strip()))
    return rows


def split_functions(rows, counts):
    """The instructions grouped into functions, each ending at a return, as
    [(address, text, samples)]; the padding between functions left out."""
    functions, current = [], []
    for address, text in rows:
        if not current and text.startswith(("nop", "data16", "cs nop", "xchg   %ax,%ax", "int3")):
            continue
        current.append((address, text, counts.get(address, 0)))
        if text.startswith("ret"):
            functions.append(current)
            current = []
    if current:
        functions.append(current)
    return functions


def call_sites(rows):
    """Calls per function address. lavapipe calls its helpers through a
    register loaded by movabs: each register is followed from its movabs to
    the calls through it, until something else writes it."""
    calls = collections.Counter()
    held = {}
    for _, text in rows:
        load = re.match(r"movabs \$(0x[0-9a-f]+),(%\w+)$", text)
        call = re.match(r"call\s+\*(%\w+)$", text)
        if load:
            held[load.group(2)] = int(load.group(1), 16)
        elif call and call.group(1) in held:
            calls[held[call.group(1)]] += 1
        else:
            written = re.search(r",(%\w+)$", text)
            if written:
                held.pop(written.group(1), None)
    return calls


def sample(command, delay, seconds, perf_data):
    """Runs `command`, samples it, and returns the sample counts by address
    and the sampled JIT code as [(start, bytes, samples)]."""
    proc = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        time.sleep(delay)
        if proc.poll() is not None:
            sys.exit(f"the command ended after {delay} s, before sampling began: give it more work")
        subprocess.run(["perf", "record", "-q", "-F", "2000", "-p", str(proc.pid), "-o", perf_data, "--", "sleep",
                        str(seconds)], check=True, stderr=subprocess.DEVNULL)
        if proc.poll() is not None:
            sys.exit("the command ended while it was sampled: its code is gone; give it more work")
        counts = sampled_ips(perf_data)
        regions = []
        try:
            with open(f"/proc/{proc.pid}/mem", "rb") as mem:
                for lo, hi in anonymous_mappings(proc.pid):
                    hits = sum(c for a, c in counts.items() if lo <= a < hi)
                    if hits:
                        mem.seek(lo)
                        regions.append((lo, mem.read(hi - lo), hits))
        except PermissionError:
            sys.exit("cannot read the process's memory: run as root, or allow ptrace (kernel.yama.ptrace_scope)")
        return counts, regions
    finally:
        proc.send_signal(signal.SIGTERM)
        proc.wait()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True, help="folder for perf.data and the annotated disassembly")
    parser.add_argument("--delay", type=float, default=8.0, help="seconds to wait before sampling (setup, checks)")
    parser.add_argument("--seconds", type=float, default=12.0, help="seconds to sample")
    parser.add_argument("--top", type=int, default=25, help="hottest instructions to print")
    parser.add_argument("command", nargs=argparse.REMAINDER, help="-- then the command to profile")
    args = parser.parse_args()
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command:
        parser.error("no command given (put it after --)")
    for tool, package in (("perf", "linux-perf"), ("objdump", "binutils")):
        if shutil.which(tool) is None:
            sys.exit(f"{tool} not found (Debian: apt-get install {package})")
    os.makedirs(args.out, exist_ok=True)
    perf_data = os.path.join(args.out, "perf.data")

    counts, regions = sample(command, args.delay, args.seconds, perf_data)
    all_samples = subprocess.run(["perf", "script", "-i", perf_data, "-F", "ip"], capture_output=True, text=True,
                                 check=True).stdout.count("\n")
    jit = sum(h for _, _, h in regions)
    if not jit:
        sys.exit("no samples in JIT code: is the command running kernels on lavapipe?")
    print(f"{all_samples} samples, {jit} ({100.0 * jit / max(all_samples, 1):.1f} %) in lavapipe's compiled kernels")

    hottest = []
    listed = []  # (samples, line) per function
    annotated = os.path.join(args.out, "annotated.s")
    with open(annotated, "w") as f:
        for lo, code, _ in regions:
            rows = disassemble(code, lo)
            calls = call_sites(rows)
            for fn in split_functions(rows, counts):
                n = sum(c for _, _, c in fn)
                if n == 0:
                    continue
                on_stack = sum(1 for _, text, _ in fn if "(%rsp" in text)
                called = calls.get(fn[0][0], 0)
                listed.append((n, f"  {100.0 * n / jit:5.1f} %  function {fn[0][0]:#x}: {len(fn):5d} instructions "
                                  f"({on_stack} reach the stack)" + (f", called from {called} places" if called else "")))
                f.write(f"# function {fn[0][0]:#x}, {n} samples\n")
                for address, text, c in fn:
                    f.write(f"{c:6d}  {address:#x}  {text}\n")
                    hottest.append((c, address, text))
    listed.sort(reverse=True)
    shown = [line for n, line in listed if n >= 0.005 * jit]
    print("functions (a kernel's body, or a helper it calls: a texel fetch is one):")
    print("\n".join(shown))
    rest = listed[len(shown):]
    if rest:
        print(f"  {100.0 * sum(n for n, _ in rest) / jit:5.1f} %  in {len(rest)} functions of under 0.5 % each")
    print("hottest instructions (a load's latency shows on the first instruction that waits for it):")
    for c, address, text in sorted(hottest, reverse=True)[:args.top]:
        print(f"  {100.0 * c / jit:5.1f} %  {address:#x}  {text}")
    print(f"annotated disassembly: {annotated}")


if __name__ == "__main__":
    main()
