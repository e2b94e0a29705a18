#!/usr/bin/env python3
"""Every declared input range tried at both ends and just outside
(docs/input_limits.md, "Ranges at their ends").

The ranges come from `gather limits`, which prints the one table they are
declared in (gather_core/input_ranges.hpp): a range added there is tried
here without a line of this file changing, and an input this file has no
driver for fails the test.

For each range:
- at each end (lo, hi, and 0 where 0 is accepted; just inside an open end)
  the command that reads the value runs to the end (exit 0) within the
  budget (--budget-s, --budget-mb of peak memory), or is refused (exit 2)
  by the rule the range declares as coupled, in one line holding that
  rule's text. A range whose work grows with the value (cycles, seeds,
  repeats, a wall-clock rate) is watched for --window-s: it must still be
  running within the memory budget, or have ended with exit 0;
- just outside each end the command refuses the value: exit 2, one line on
  stderr of at most 300 characters naming the key.
Also, every key of the table is named in docs/input_limits.md.

The commands: a scenario's fields and a map's with `gather plan SCENARIO
--config bap:1` (bap:0 when the team is one robot) on maps/office; plan.yaml's
with `gather run PLAN --cycles 1`; every flag with its own command on the
same scenario and plan (gather run --rate with --lcm: this runs inside
tools/netns-run); gather_agent alone on memq:// (it runs until its
--silence, then says nothing was heard from the OC); mission_bag's flag up
to reading the recording (a recording needs a wall-clock mission on a
network: tests/e2e/hosts_e2e.py plays one through mission_bag).

  tests/cli/range_ends.py --gather G --agent A --mission-bag B [--jobs 2]
"""
import argparse
import concurrent.futures
import itertools
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", ".."))
OFFICE = os.path.join(REPO, "maps", "office.scenario.yaml")
DOCS = os.path.join(REPO, "docs", "input_limits.md")


class Range:
    def __init__(self, row):
        self.input, self.key, lo, hi, self.unit, flags, coupled = row
        self.lo, self.hi = float(lo), float(hi)
        self.flags = set() if flags == "-" else set(flags.split(","))
        self.coupled = None if coupled == "-" else coupled
        self.integer = "int" in self.flags

    def name(self):
        return "%s %s" % (self.input, self.key)

    def fmt(self, v):
        if self.integer:
            return str(int(v))
        return repr(float(v))

    def step(self, v):
        return 1 if self.integer else max(abs(v) * 1e-6, 1e-6)

    def ends(self):
        lo = self.lo + self.step(self.lo) if "open_lo" in self.flags else self.lo
        hi = self.hi - self.step(self.hi) if "open_hi" in self.flags else self.hi
        out = [("lo", lo), ("hi", hi)]
        if "zero" in self.flags:
            out.append(("zero", 0))
        return out

    def outside(self):
        below = self.lo if "open_lo" in self.flags else self.lo - self.step(self.lo)
        above = self.hi if "open_hi" in self.flags else self.hi + self.step(self.hi)
        return [("below lo", below), ("above hi", above)]


def read_ranges(gather):
    out = subprocess.run([gather, "limits"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=30)
    if out.returncode != 0:
        sys.exit("gather limits failed (%d): %s" % (out.returncode, out.stderr.strip()))
    rows = [line.split("\t") for line in out.stdout.splitlines()]
    if not rows or rows[0][:2] != ["input", "key"]:
        sys.exit("gather limits: no header line")
    return [Range(r) for r in rows[1:]]


def watch(argv, limit_s, cwd):
    """Runs argv; returns (status or None when still running at limit_s and
    killed, stderr text, wall s, peak RSS in MB)."""
    err_path = os.path.join(cwd, "stderr.txt")
    with open(err_path, "w") as err:
        p = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=err, cwd=cwd, start_new_session=True)
    t0 = time.monotonic()
    status, peak_kb = None, 0
    while True:
        pid, st, ru = os.wait4(p.pid, os.WNOHANG)
        if pid == p.pid:
            status = os.waitstatus_to_exitcode(st)
            peak_kb = max(peak_kb, ru.ru_maxrss)
            break
        try:
            with open("/proc/%d/status" % p.pid) as f:
                m = re.search(r"VmHWM:\s+(\d+) kB", f.read())
                if m:
                    peak_kb = max(peak_kb, int(m.group(1)))
        except OSError:
            pass
        if time.monotonic() - t0 > limit_s:
            os.killpg(p.pid, signal.SIGKILL)
            _, _, ru = os.wait4(p.pid, 0)
            peak_kb = max(peak_kb, ru.ru_maxrss)
            break
        time.sleep(0.02)
    wall = time.monotonic() - t0
    with open(err_path) as f:
        text = f.read()
    return status, text, wall, peak_kb / 1024.0


class Drivers:
    """The command line that reads each input, with the value set."""

    def __init__(self, a, work):
        self.a, self.work = a, work
        with open(OFFICE) as f:
            self.scenario = yaml.safe_load(f)
        self.scenario["map"] = os.path.join(REPO, "maps", "office.yaml")
        with open(self.scenario["map"]) as f:
            self.map = yaml.safe_load(f)
        self.map["image"] = os.path.join(REPO, "maps", self.map["image"])
        self.base_scenario = os.path.join(work, "base.scenario.yaml")
        self.write_yaml(self.base_scenario, self.scenario)
        self.plan = os.path.join(work, "plan")
        r = subprocess.run([a.gather, "plan", self.base_scenario, "--config", "pap:1", "--out", self.plan],
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, timeout=120)
        if r.returncode != 0:
            sys.exit("gather plan of the base scenario failed: " + r.stderr.strip())
        self.key = os.path.join(work, "fleet.key")
        self.ports = itertools.count()
        subprocess.run([a.gather, "keygen", self.key], stdout=subprocess.DEVNULL, check=True, timeout=30)
        self.commands = {
            "gather plan": lambda d: [a.gather, "plan", self.base_scenario, "--config", "bap:1", "--out", d],
            "gather sim": lambda d: [a.gather, "sim", self.plan, "--cycles", "1", "--out", d],
            "gather run": lambda d: [a.gather, "run", self.plan, "--cycles", "1", "--out", d],
            "gather partition": lambda d: [a.gather, "partition", self.base_scenario, "--method", "bap", "--workers",
                                           "4", "--out", d],
            "gather partition --report": lambda d: [a.gather, "partition", "--report", "--workers", "4", "--repeat",
                                                    "1", self.base_scenario],
            "gather fmm": lambda d: [a.gather, "fmm", "--map", self.scenario["map"], "--source", "350,110"],
            "gather radio": lambda d: [a.gather, "radio", self.base_scenario, "--repeat", "1"],
            "gather keygen": lambda d: [a.gather, "keygen", os.path.join(d, "k.key")],
            "gather keygen --agent": lambda d: [a.gather, "keygen", os.path.join(d, "k.key"), "--agent", "0", "--plan",
                                                self.plan, "--master", self.key],
            "gather_agent": lambda d: [a.agent, "--id", "0", "--plan", self.plan, "--key-file", self.key, "--lcm-url",
                                       "memq://", "--silence", "1"],
            "mission_bag": lambda d: [a.mission_bag, self.plan, "--replay", os.path.join(d, "none.log"), "--key-file",
                                      self.key, "--out", os.path.join(d, "bag")],
        }

    @staticmethod
    def write_yaml(path, doc):
        with open(path, "w") as f:
            yaml.safe_dump(doc, f, sort_keys=False)

    @staticmethod
    def set_path(doc, key, value):
        """doc at the YAML path key ("team.speed", "oc[0]") = value."""
        parts = key.split(".")
        for part in parts[:-1]:
            doc = doc.setdefault(part, {})
        m = re.fullmatch(r"(\w+)\[(\d+)\]", parts[-1])
        if m:
            doc[m.group(1)][int(m.group(2))] = value
        else:
            doc[parts[-1]] = value

    def has(self, r):
        return r.input in ("scenario", "map", "plan") or r.input in self.commands

    def argv(self, r, text, d):
        """The command reading `text` as the value of range r, run in d."""
        value = int(text) if r.integer else float(text)
        if r.input in ("scenario", "map"):
            sc = yaml.safe_load(yaml.safe_dump(self.scenario))
            if r.input == "scenario":
                if r.key.startswith("planner.collectors"):
                    sc["planner"]["collectors"] = [0, 1]
                self.set_path(sc, r.key, value)
            else:
                m = yaml.safe_load(yaml.safe_dump(self.map))
                self.set_path(m, r.key, value)
                sc["map"] = os.path.join(d, "map.yaml")
                self.write_yaml(sc["map"], m)
            path = os.path.join(d, "s.scenario.yaml")
            self.write_yaml(path, sc)
            agents = sc["team"]["agents"]
            return [self.a.gather, "plan", path, "--config", "bap:%d" % min(1, agents - 1), "--threads", "1",
                    "--out", os.path.join(d, "out")]
        if r.input == "plan":
            plan = os.path.join(d, "plan")
            shutil.copytree(self.plan, plan)
            pf = os.path.join(plan, "plan.yaml")
            with open(pf) as f:
                body = f.read()
            line = "%s: %s" % (r.key, text)
            body, n = re.subn(r"(?m)^%s:.*$" % re.escape(r.key), line, body)
            if n == 0:
                body += line + "\n"
            with open(pf, "w") as f:
                f.write(body)
            return [self.a.gather, "run", plan, "--cycles", "1", "--out", os.path.join(d, "out")]
        argv = self.commands[r.input](d)
        if r.key == "--rate":  # the rate of the fleet over LCM, in this private namespace, a port of its own
            port = 7700 + 2 * next(self.ports)
            argv += ["--lcm", "--key-file", self.key, "--lcm-url", "udpm://239.255.76.67:%d?ttl=0" % port,
                     "--reply-url", "udpm://239.255.76.67:%d?ttl=0" % (port + 1)]
        if r.key in argv:  # the base line's own value of this flag is replaced
            i = argv.index(r.key)
            del argv[i:i + 2]
        return argv + [r.key, text]


def one_line(text):
    lines = [line for line in text.splitlines() if line.strip()]
    return lines[-1] if len(lines) == 1 else None


def probe(drivers, r, what, value, a):
    d = tempfile.mkdtemp(dir=drivers.work)
    text = r.fmt(value)
    argv = drivers.argv(r, text, d)
    work = "work" in r.flags
    status, err, wall, peak = watch(argv, a.window_s if work else a.budget_s, d)
    shown = "%s = %s (%s): exit %s, %.1f s, %.0f MB" % (r.name(), text, what, status, wall, peak)
    line = one_line(err)
    problems = []
    if what in ("lo", "hi", "zero"):
        if peak > a.budget_mb:
            problems.append("peak memory %.0f MB over the budget %d MB" % (peak, a.budget_mb))
        if status is None:
            if not work:
                problems.append("still running after %d s" % a.budget_s)
        elif status == 0:
            pass
        elif status == 2 and r.coupled and line is not None and any(c in line for c in r.coupled.split("|")):
            shown += " (refused by the coupled rule)"
        elif r.input == "gather_agent" and status == 1 and "nothing heard from the OC" in err:
            pass  # ran until its silence: no OC on memq://
        elif r.input == "mission_bag" and status == 2 and line is not None and "none.log" in line:
            shown += " (accepted; refused at the recording)"
        else:
            problems.append("an end of the range must run (exit 0) or be refused by its coupled rule (%s); stderr: %s"
                            % (r.coupled, err.strip()[-300:]))
    else:
        if status != 2 or line is None or len(line) > 300 or r.key.split("[")[0] not in line:
            problems.append("a value outside the range must be refused: exit 2, one line of at most 300 characters "
                            "naming %s; stderr: %s" % (r.key, err.strip()[-300:]))
    shutil.rmtree(d, ignore_errors=True)
    return shown, problems


# Ends that multiply: several fields at their ends at once, planned
# (gather plan --config bap:1) and then simulated (gather sim, which draws
# Fig. 4). Each must run within the budget or be refused in one line holding
# the text given (docs/input_limits.md, "Memory and time"); a simulation
# whose time grows with what it asks for (the last field: True) is watched
# for --window-s x 2 and must stay within the memory budget.
PRODUCTS = [
    ("the fastest team over the longest period (Fig. 4)", {"team.speed": 100.0, "mission.period": 100000.0}, None,
     False),
    ("the most goals over the most cycles", {"mission.goals_per_request": 5000, "mission.cycles": 10000},
     "goal records", False),
    ("the most goals a request at the goal budget", {"mission.goals_per_request": 5000, "mission.cycles": 200}, None,
     True),
    ("the most cycles at the goal budget", {"mission.goals_per_request": 100, "mission.cycles": 10000}, None, True),
    ("the largest team on the map's own grid", {"team.agents": 300, "planner.max_cells": 0}, None, False),
]


def product(drivers, name, fields, refusal, work, a):
    d = tempfile.mkdtemp(dir=drivers.work)
    sc = yaml.safe_load(yaml.safe_dump(drivers.scenario))
    for key, value in fields.items():
        Drivers.set_path(sc, key, value)
    path = os.path.join(d, "s.scenario.yaml")
    Drivers.write_yaml(path, sc)
    plan = os.path.join(d, "plan")
    steps = [[a.gather, "plan", path, "--config", "bap:1", "--out", plan],
             [a.gather, "sim", plan, "--out", os.path.join(d, "sim")]]
    shown, problems = "%s (%s)" % (name, ", ".join("%s = %s" % kv for kv in fields.items())), []
    for argv in steps:
        watched = work and argv[1] == "sim"
        status, err, wall, peak = watch(argv, a.window_s * 2 if watched else a.budget_s * 2, d)
        shown += "; %s: exit %s, %.1f s, %.0f MB" % (argv[1], status, wall, peak)
        line = one_line(err)
        if status == 2 and refusal and line is not None and refusal in line:
            break
        if watched and status is None and peak <= a.budget_mb:
            shown += " (watched)"
            continue
        if status != 0 or peak > a.budget_mb or wall > a.budget_s * 2:
            problems.append("gather %s must run within %d s and %d MB or be refused naming %s; stderr: %s"
                            % (argv[1], a.budget_s * 2, a.budget_mb, refusal, err.strip()[-300:]))
            break
    shutil.rmtree(d, ignore_errors=True)
    return shown, problems


def largest_map(a):
    """The largest image a map may have (8000 x 8000 pixels, 64M cells,
    free inside a wall), through every command that reads a map: each runs
    within the budget or is refused up front naming the budget. About 20 s
    and 64 MB of disk: --largest-map (make test-cli runs it)."""
    d = tempfile.mkdtemp(prefix="range_ends_map.")
    w = h = 8000
    with open(os.path.join(d, "big.pgm"), "wb") as f:
        f.write(b"P5\n%d %d\n255\n" % (w, h))
        wall, row = bytes([0]) * w, bytes([0]) + bytes([254]) * (w - 2) + bytes([0])
        f.write(wall + row * (h - 2) + wall)
    with open(os.path.join(d, "big.yaml"), "w") as f:
        f.write("image: big.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
                "free_thresh: 0.196\n")
    sc = {"map": "big.yaml", "oc": [200.0, 200.0], "team": {"agents": 20, "speed": 0.5}}
    Drivers.write_yaml(os.path.join(d, "big.scenario.yaml"), sc)
    sc["planner"] = {"max_cells": 0}
    Drivers.write_yaml(os.path.join(d, "own_grid.scenario.yaml"), sc)
    s, own = os.path.join(d, "big.scenario.yaml"), os.path.join(d, "own_grid.scenario.yaml")
    cases = [("gather info", [a.gather, "info", s], None),
             ("gather fmm", [a.gather, "fmm", "--map", os.path.join(d, "big.yaml"), "--source", "4000,4000"], None),
             ("gather radio", [a.gather, "radio", s, "--repeat", "1"], None),
             ("gather plan (planning grid)", [a.gather, "plan", s, "--config", "bap:1", "--out", os.path.join(d, "p")],
              None),
             ("gather plan (the map's own grid)", [a.gather, "plan", own, "--out", os.path.join(d, "q")], "budget"),
             ("gather partition", [a.gather, "partition", s, "--method", "bap", "--workers", "20", "--out",
                                   os.path.join(d, "r")], "budget")]
    failures = []
    for name, argv, refusal in cases:
        status, err, wall, peak = watch(argv, a.budget_s * 3, d)
        line = one_line(err)
        ok = peak <= a.budget_mb and (status == 0 or (status == 2 and refusal and line and refusal in line))
        print("%s %s on the largest map: exit %s, %.1f s, %.0f MB%s" % ("ok  " if ok else "FAIL", name, status, wall,
                                                                      peak, "" if ok else "; " + err.strip()[-300:]))
        if not ok:
            failures.append(name)
    shutil.rmtree(d, ignore_errors=True)
    return 1 if failures else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gather", required=True)
    ap.add_argument("--agent", required=True)
    ap.add_argument("--mission-bag", required=True)
    ap.add_argument("--budget-s", type=float, default=20.0, help="time an end may take [s]")
    ap.add_argument("--budget-mb", type=int, default=1024, help="peak memory an end may take [MB]")
    ap.add_argument("--window-s", type=float, default=4.0, help="how long a range whose work grows is watched [s]")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", default="", help="only the ranges whose key holds this text ('products': only the ends "
                    "that multiply)")
    ap.add_argument("--largest-map", action="store_true", help="only the commands on the largest map (slow)")
    a = ap.parse_args()
    if a.largest_map:
        a.gather = os.path.abspath(a.gather)
        return largest_map(a)
    a.gather, a.agent, a.mission_bag = (os.path.abspath(p) for p in (a.gather, a.agent, a.mission_bag))
    if os.environ.get("GATHER_NETNS") != "1":
        sys.exit("range_ends.py runs gather run --lcm: run it inside tools/netns-run")
    ranges = read_ranges(a.gather)
    failures = []
    with open(DOCS) as f:
        docs = f.read()
    for r in ranges:
        if "`%s`" % r.key not in docs:
            failures.append("%s: not in docs/input_limits.md (as `%s`)" % (r.name(), r.key))
    work = tempfile.mkdtemp(prefix="range_ends.")
    try:
        drivers = Drivers(a, work)
        jobs = []
        for r in ranges:
            if a.only and a.only not in r.key:
                continue
            if not drivers.has(r):
                failures.append("%s: no driver for input '%s' (add one to tests/cli/range_ends.py)" % (r.name(), r.input))
                continue
            jobs += [(r, what, v) for what, v in r.ends() + r.outside()]
        with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
            results = list(pool.map(lambda j: probe(drivers, j[0], j[1], j[2], a), jobs))
            if not a.only or a.only == "products":
                results += list(pool.map(lambda p: product(drivers, p[0], p[1], p[2], p[3], a), PRODUCTS))
            for shown, problems in results:
                print(("FAIL " if problems else "ok   ") + shown + "".join("\n     " + p for p in problems),
                      flush=True)
                failures += [shown + ": " + p for p in problems]
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("range_ends: %d ranges, %d probes, %d failures" % (len(ranges), len(jobs), len(failures)))
    for f in failures:
        print("FAIL " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
