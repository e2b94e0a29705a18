#!/usr/bin/python3
"""A seeded mutation fuzz smoke over the inputs of `gather` and `gather_agent`.

Run against a sanitized build (make test-plain: -fsanitize=address,undefined,
float-cast-overflow, any report aborts):

  tests/fuzz/fuzz_smoke.py --gather build/plain/gather_core/gather \
      --agent build/plain/gather_agent [--cases 300] [--seed 1]

It makes a small valid world (a 12 m x 8 m map, 4 agents, a plan of it) in a
temporary directory and mutates, case by case, one of: the scenario YAML,
the map YAML, the map image (PGM or PNG bytes), plan.yaml, the label image,
or the command-line flags. YAML mutations include nasty numbers (range
ends, NaN, huge), control characters, aliases of an anchor, flow lists of
up to 150,000 numbers and empty strings (paths). Each case runs one command (gather info / plan /
sim / run, gather_agent) under a 20 s timeout. A case fails when the process
is killed by a signal, a sanitizer reports (AddressSanitizer, LeakSanitizer,
"runtime error:"), it runs longer than 20 s, its peak RSS exceeds 1 GiB, it
exits with a status other than 0, 1 or 2, or it exits 2 with anything but
exactly one line on stderr. The key files (the master, an agent's own) are
mutated too. LCM payloads
and envelopes are fuzzed by the unit tests LcmFleet.Mutated... and
LcmFleetAuthTest (in the same sanitized build).

Prints one line per failing case (with the input kept under --keep DIR) and a
summary; exits 1 if any case failed.
"""
import argparse
import collections
import concurrent.futures
import os
import random
import re
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import zlib

TIMEOUT_S = 20.0
MAX_RSS_KB = 1 << 20  # 1 GiB
SANITIZER = re.compile(rb"AddressSanitizer|LeakSanitizer|runtime error:|UndefinedBehaviorSanitizer")
# Library exception texts: a bug escaping as "bad input" (gather maps every
# std::exception to exit 2), not a validated error naming a file and key.
LIBRARY_TEXT = re.compile(r"std::|vector::|basic_string|bad_alloc|bad conversion|stoi|stod|_M_")

# Values a mutation puts in place of a number.
NASTY = [".nan", ".inf", "-.inf", "1e300", "-1e300", "0", "-1", "2147483647", "-2147483648", "4294967296",
         "1e-300", "0.0001", "99999999999999999999", "3.5", "-0.0", "1e9", "\"x\"", "[1, 2]", "{}", "~"]
NUMBER = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?(?:e[-+]?\d+)?(?![\w.])")


def pgm(rows):
    return b"P5\n%d %d\n255\n" % (len(rows[0]), len(rows)) + bytes(v for r in rows for v in r)


def png(rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", len(rows[0]), len(rows), 8, 0, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def world_image():
    # 48 x 32 cells at 0.25 m: walls round, a wall with a door in the middle.
    w, h = 48, 32
    rows = [[254] * w for _ in range(h)]
    for c in range(w):
        rows[0][c] = rows[h - 1][c] = 0
    for r in range(h):
        rows[r][0] = rows[r][w - 1] = 0
        if not 12 <= r <= 18:
            rows[r][24] = 0
    return rows


SCENARIO = """map: map.yaml
oc: [1.0, 1.0]
team:
  agents: 4
  speed: 0.5
radio:
  tx_power_dbm: 0.0
  ref_loss_db: 40.0
  exponent: 3.0
  wall_loss_db: 5.0
  max_walls: 4
  sensitivity_dbm: -60.0
  bitrate_bps: 8000
mission:
  goals_per_request: 8
  cycles: 2
  seed: 1
  period: 60
  bytes_per_goal: 4096
planner:
  methods: [bap, pap]
  collectors: [0, 1]
"""

MAP_YAML = """image: {image}
resolution: 0.25
origin: [0.0, 0.0, 0.0]
negate: 0
occupied_thresh: 0.65
free_thresh: 0.196
"""


class Fuzzer:
    def __init__(self, a):
        self.a = a
        self.rng = random.Random(a.seed)
        self.tmp = tempfile.mkdtemp(prefix="gather_fuzz_")
        self.base = os.path.join(self.tmp, "base")
        os.makedirs(self.base)
        img = world_image()
        self.write(self.base, "map.pgm", pgm(img))
        self.write(self.base, "map.png", png(img))
        self.write(self.base, "map.yaml", MAP_YAML.format(image="map.pgm"))
        self.write(self.base, "scenario.yaml", SCENARIO)
        out = os.path.join(self.base, "plan")
        r = subprocess.run([a.gather, "plan", os.path.join(self.base, "scenario.yaml"), "--config", "pap:1",
                            "--association", "off", "--out", out], capture_output=True, timeout=120)
        if r.returncode != 0:
            sys.exit("fuzz_smoke: cannot plan the base world: " + r.stderr.decode(errors="replace")[-400:])
        r = subprocess.run([a.gather, "keygen", os.path.join(self.base, "fleet.key")], capture_output=True, timeout=60)
        if r.returncode != 0:
            sys.exit("fuzz_smoke: cannot make a fleet key: " + r.stderr.decode(errors="replace")[-400:])
        r = subprocess.run([a.gather, "keygen", os.path.join(self.base, "agent0.key"), "--agent", "0", "--plan", out,
                            "--master", os.path.join(self.base, "fleet.key")], capture_output=True, timeout=60)
        if r.returncode != 0:
            sys.exit("fuzz_smoke: cannot make agent 0's key: " + r.stderr.decode(errors="replace")[-400:])
        self.failures = 0
        self.kinds = {}
        self.statuses = {}
        self.runtime = {}  # exit-1 messages (numbers and paths masked) -> cases

    @staticmethod
    def write(d, name, data):
        with open(os.path.join(d, name), "wb") as f:
            f.write(data.encode() if isinstance(data, str) else data)

    # --- mutations -----------------------------------------------------------
    def mutate_text(self, text):
        r = self.rng
        lines = text.split("\n")
        for _ in range(1 + r.randrange(3)):
            op = r.randrange(9)
            i = r.randrange(len(lines))
            if op <= 2:  # a number replaced by a nasty value
                nums = list(NUMBER.finditer(lines[i]))
                if nums:
                    m = r.choice(nums)
                    lines[i] = lines[i][:m.start()] + r.choice(NASTY) + lines[i][m.end():]
            elif op == 3:
                del lines[i]
            elif op == 4:
                lines.insert(i, lines[r.randrange(len(lines))])
            elif op == 5:
                pos = r.randrange(len(lines[i]) + 1)
                lines[i] = lines[i][:pos] + r.choice(["{", "[", ":", "'", "\t", "#", "\x00", "x" * 2000]) + lines[i][pos:]
            elif op == 6:  # an anchor on one value and an alias of it on another (refused: aliases)
                j = r.randrange(len(lines))
                a, b = NUMBER.search(lines[i]), NUMBER.search(lines[j])
                if a and b and i != j:
                    lines[i] = lines[i][:a.start()] + "&v " + lines[i][a.start():]
                    lines[j] = lines[j][:b.start()] + "*v" + lines[j][b.end():]
            elif op == 7:  # a value that becomes a flow list of many numbers (sizes that multiply)
                nums = list(NUMBER.finditer(lines[i]))
                if nums:
                    m = r.choice(nums)
                    many = "[" + ",".join(["1"] * r.choice([1000, 99000, 150000])) + "]"
                    lines[i] = lines[i][:m.start()] + many + lines[i][m.end():]
            else:  # a value made an empty string (an empty path names its key)
                k = lines[i].find(": ")
                if k >= 0:
                    lines[i] = lines[i][:k + 2] + '""'

            if not lines:
                lines = [""]
        return "\n".join(lines)

    def mutate_bytes(self, b):
        r = self.rng
        b = bytearray(b)
        op = r.randrange(4)
        if op == 0:
            for _ in range(1 + r.randrange(8)):
                b[r.randrange(len(b))] ^= 1 << r.randrange(8)
        elif op == 1:
            del b[r.randrange(len(b)):]
        elif op == 2:  # header numbers (PGM) or IHDR size (PNG) made huge or zero
            if b[:2] == b"P5":
                b = bytearray(re.sub(rb"^P5\n\d+ \d+", b"P5\n%d %d" % (r.choice([0, 1, 70000, 9000]),
                                                                      r.choice([0, 1, 70000, 9000])), bytes(b)))
            else:  # the IHDR's width and height, with its CRC made right again (else libpng stops at the CRC)
                struct.pack_into(">II", b, 16, r.choice([0, 1, 9000, 70000, 2 ** 31 - 1]), r.choice([0, 1, 9000, 70000]))
                struct.pack_into(">I", b, 29, zlib.crc32(bytes(b[12:29])) & 0xFFFFFFFF)
        else:
            for _ in range(1 + r.randrange(4)):
                b[r.randrange(len(b))] = r.choice([0, 0xff, 0x7f, 0x80])
        return bytes(b)

    def case_dir(self, n):
        d = os.path.join(self.tmp, "case%04d" % n)
        shutil.copytree(self.base, d)
        return d

    def make_case(self, n):
        """Returns (kind, argv, directory)."""
        r = self.rng
        d = self.case_dir(n)
        g, plan = self.a.gather, os.path.join(d, "plan")
        kind = r.choice(["scenario", "map_yaml", "image", "plan_yaml", "labels", "flags", "flags", "plan_yaml",
                         "scenario", "key"])
        key = os.path.join(d, "fleet.key")
        if kind == "scenario":
            # Mutated, then loaded (info), planned, or executed with the plan
            # made from the original (which names this case's scenario).
            p = os.path.join(d, "scenario.yaml")
            self.write(d, "scenario.yaml", self.mutate_text(open(p).read()))
            self.write(plan, "plan.yaml", open(os.path.join(plan, "plan.yaml")).read().replace(
                os.path.join(self.base, "scenario.yaml"), p))
            argv = r.choice([[g, "info", p], [g, "plan", p, "--config", "bap:1", "--out", os.path.join(d, "out")],
                             [g, "sim", plan, "--cycles", "2", "--out", os.path.join(d, "sim")],
                             [g, "run", plan, "--cycles", "1", "--out", os.path.join(d, "run")]])
        elif kind == "map_yaml":
            self.write(d, "map.yaml", self.mutate_text(open(os.path.join(d, "map.yaml")).read()))
            argv = [g, "info", os.path.join(d, "scenario.yaml")]
        elif kind == "image":
            name = r.choice(["map.pgm", "map.png"])
            self.write(d, "map.yaml", MAP_YAML.format(image=name))
            self.write(d, name, self.mutate_bytes(open(os.path.join(d, name), "rb").read()))
            argv = [g, "info", os.path.join(d, "scenario.yaml")]
        elif kind in ("plan_yaml", "labels"):
            if kind == "plan_yaml":
                p = os.path.join(plan, "plan.yaml")
                text = open(p).read().replace(os.path.join(self.base, "scenario.yaml"), os.path.join(d, "scenario.yaml"))
                self.write(plan, "plan.yaml", self.mutate_text(text))
            else:
                p = os.path.join(plan, "plan.yaml")
                self.write(plan, "plan.yaml", open(p).read().replace(os.path.join(self.base, "scenario.yaml"),
                                                                      os.path.join(d, "scenario.yaml")))
                self.write(plan, "labels.png", self.mutate_bytes(open(os.path.join(plan, "labels.png"), "rb").read()))
            argv = r.choice([[g, "sim", plan, "--cycles", "2", "--out", os.path.join(d, "sim")],
                             [g, "run", plan, "--cycles", "1", "--out", os.path.join(d, "run")],
                             [self.a.agent, "--id", str(r.randrange(4)), "--lcm-url", "memq://", "--silence", "0.5",
                              "--key-file", key, "--plan", plan]])
        elif kind == "key":
            # A mutated key file (mode 0600): the master or agent 0's own, read by the agent.
            key = os.path.join(d, r.choice(["fleet.key", "agent0.key"]))
            self.write(d, os.path.basename(key), self.mutate_text(open(key).read()))
            os.chmod(key, 0o600)
            argv = [self.a.agent, "--id", "0", "--lcm-url", "memq://", "--silence", "0.5", "--key-file", key,
                    "--plan", plan]
        else:
            cmd = r.choice(["sim", "run", "plan", "fmm"])
            flags = {"sim": ["--cycles", "--seeds", "--seed", "--threads"],
                     "run": ["--cycles", "--seeds", "--seed", "--tick", "--loss", "--loss-seed", "--rate", "--kill",
                             "--repair", "--silent-intervals"],
                     "plan": ["--seed", "--threads", "--config", "--association"],
                     "fmm": ["--order", "--repeat", "--bucket-width", "--max-time", "--source", "--sources-file"]}[cmd]
            extra = []
            for _ in range(1 + r.randrange(2)):
                f = r.choice(flags)
                v = r.choice(NASTY + ["pap:99", "rap:-1", "x:1", "1,1", "/dev/zero", "0,0", "2,2", "on", "off",
                                      "1@5", "0@0,1@3", "3@nan", "1@1e300", "99@5", "1@5,1@6", "merge", "none"])
                extra += [f, v.strip('"')]
            if cmd == "sim":
                argv = [g, "sim", plan, "--out", os.path.join(d, "sim")] + extra
            elif cmd == "run":
                argv = [g, "run", plan, "--out", os.path.join(d, "run")] + extra
            elif cmd == "plan":
                argv = [g, "plan", os.path.join(d, "scenario.yaml"), "--out", os.path.join(d, "out")] + extra
            else:
                argv = [g, "fmm", "--map", os.path.join(d, "map.yaml"), "--source", "10,10",
                        "--out", os.path.join(d, "fmm.csv")] + extra
        return kind, argv, d

    def run_case(self, n, case):
        """Runs one case made by make_case (in any thread); returns its verdict."""
        kind, argv, d = case
        t0 = time.monotonic()
        with tempfile.TemporaryFile() as fo, tempfile.TemporaryFile() as fe:
            p = subprocess.Popen(argv, stdout=fo, stderr=fe, stdin=subprocess.DEVNULL, cwd=d,
                                 env=dict(os.environ, ASAN_OPTIONS="detect_leaks=1:exitcode=99",
                                          UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:exitcode=99"))
            why = ""
            # Reaped here (not by Popen) to get this child's own peak RSS.
            while True:
                pid, wstatus, usage = os.wait4(p.pid, os.WNOHANG)
                if pid == p.pid:
                    break
                if time.monotonic() - t0 > TIMEOUT_S:
                    p.kill()
                    pid, wstatus, usage = os.wait4(p.pid, 0)
                    why = "hang: still running after %.0f s" % TIMEOUT_S
                    break
                time.sleep(0.01)
            p.returncode = os.waitstatus_to_exitcode(wstatus)
            rss = usage.ru_maxrss
            fo.seek(0), fe.seek(0)
            out, err = fo.read(), fe.read()
        status = p.returncode
        lines = err.decode(errors="replace").strip("\n").split("\n") if err.strip() else []
        if why:
            pass
        elif SANITIZER.search(err):
            why = "sanitizer report: " + next((l for l in lines if "Sanitizer" in l or "runtime error" in l), lines[0])
        elif b"(internal error)" in err:
            why = "an internal error from bad input (validation missed it): " + lines[-1][:300]
        elif status < 0:
            why = "killed by signal %s" % signal.Signals(-status).name
        elif status not in (0, 1, 2):
            why = "exit status %d" % status
        elif rss > MAX_RSS_KB:
            why = "peak RSS %d MB over 1 GiB" % (rss // 1024)
        elif status == 2 and len(lines) != 1:
            why = "exit 2 with %d lines on stderr (one expected): %s" % (len(lines), " | ".join(lines)[:300])
        elif status == 2 and LIBRARY_TEXT.search(lines[0]):
            why = "exit 2 with a library's exception text, not a validated error: " + lines[0][:300]
        report = ""
        if why:
            keep = os.path.join(self.a.keep, "case%04d" % n)
            shutil.rmtree(keep, ignore_errors=True)
            shutil.copytree(d, keep)
            report = "FAIL case %d (%s, %.1f s): %s\n     %s\n     input kept in %s" % (
                n, kind, time.monotonic() - t0, why[:400], " ".join(argv)[:300], keep)
        shutil.rmtree(d, ignore_errors=True)
        # A runtime failure (exit 1) is allowed, but named in the summary:
        # bad input should be refused (2), not fail later.
        runtime = re.sub(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?|/\S+", "#", lines[-1])[:90] if status == 1 and lines else ""
        return kind, status, report, runtime

    def count(self, verdict):
        kind, status, report, runtime = verdict
        self.kinds[kind] = self.kinds.get(kind, 0) + 1
        if runtime:
            self.runtime[runtime] = self.runtime.get(runtime, 0) + 1
        self.statuses[status] = self.statuses.get(status, 0) + 1
        if report:
            self.failures += 1
            print(report, flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gather", required=True)
    ap.add_argument("--agent", required=True)
    ap.add_argument("--cases", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--keep", default="results/fuzz")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="cases run at once (the cases and their order do not depend on it)")
    a = ap.parse_args()
    a.gather, a.agent, a.keep = os.path.abspath(a.gather), os.path.abspath(a.agent), os.path.abspath(a.keep)
    t0 = time.monotonic()
    f = Fuzzer(a)
    try:
        # Cases are made one after another from the one seeded generator (so
        # the same seed gives the same cases whatever --jobs is) and run
        # `jobs` at a time; verdicts are counted and printed in case order.
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
            running = collections.deque()
            for n in range(a.cases):
                running.append(pool.submit(f.run_case, n, f.make_case(n)))
                while len(running) > 2 * max(1, a.jobs):
                    f.count(running.popleft().result())
            while running:
                f.count(running.popleft().result())
    finally:
        shutil.rmtree(f.tmp, ignore_errors=True)
    print("fuzz smoke: %d cases (%s; exit status %s), seed %d, %.0f s: %d failed" % (
        a.cases, ", ".join("%s %d" % kv for kv in sorted(f.kinds.items())),
        ", ".join("%d: %d" % kv for kv in sorted(f.statuses.items())), a.seed, time.monotonic() - t0, f.failures))
    for msg, k in sorted(f.runtime.items(), key=lambda kv: -kv[1]):
        print("  exit 1 in %d case(s): %s" % (k, msg))
    return 1 if f.failures else 0


if __name__ == "__main__":
    sys.exit(main())
