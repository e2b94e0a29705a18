#!/usr/bin/env python3
"""Benchmark of the agent runtime on maps/office, 20 agents, 10 cycles
(`make bench-runtime`; docs/runtime.md quotes it).

- In one process (`gather run`): mission time / wall time of the run, over
  RUNS seeds (median, min, max), for the scenario's best plan (bap, no
  collectors) and a plan with collectors (pap, 4).
- One process per agent over LCM (`gather run --lcm`, inside a private
  network namespace): the same, over RUNS seeds, with the radio messages per
  second and where the wall time of a tick goes (from `gather run`'s own
  report), and each agent process's peak resident memory (`/usr/bin/time`
  around every agent: median and max over the 20 agents of each run).

Whole-command wall time (start-up, loading, planning of the team) is shown
beside the run's own figure. Prints a Markdown table.

  tools/netns-run python3 bench/runtime_bench.py [--runs 5] [--gather PATH]
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))


def med(xs):
    return statistics.median(xs) if xs else float("nan")


def run(cmd, timeout=600):
    t0 = time.perf_counter()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit("runtime_bench: %s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr[-800:]))
    return p.stdout, wall


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--cycles", type=int, default=10)
    ap.add_argument("--gather", default=os.path.join(REPO, "catkin_ws", "devel", "lib", "gather_core", "gather"))
    ap.add_argument("--agent", default=os.path.join(REPO, "catkin_ws", "devel", "lib", "gather_agent", "gather_agent"))
    a = ap.parse_args()
    if os.environ.get("GATHER_NETNS") != "1":
        sys.exit("runtime_bench: run me inside tools/netns-run (LCM multicast must stay in a private namespace)")
    tmp = tempfile.mkdtemp(prefix="gather_runtime_bench_")
    key = os.path.join(tmp, "fleet.key")  # the runs over LCM sign their traffic (docs/security.md)
    subprocess.run([a.gather, "keygen", key], check=True, stdout=subprocess.DEVNULL)
    scenario = os.path.join(REPO, "maps", "office.scenario.yaml")
    wrapper = os.path.join(tmp, "agent.sh")
    with open(wrapper, "w") as f:
        f.write("#!/bin/bash\nexec /usr/bin/time -f %%M -o %s/mem.$2 %s \"$@\"\n" % (tmp, a.agent))
    os.chmod(wrapper, 0o755)

    rows = []
    for config in ("bap:0", "pap:4"):
        plan = os.path.join(tmp, config.replace(":", ""))
        run([a.gather, "plan", scenario, "--config", config, "--out", plan])
        one, one_wall, lcm, lcm_wall, rates, ticks, mem_med, mem_max = [], [], [], [], [], [], [], []
        for k in range(a.runs):
            seed = str(k + 1)
            out, wall = run([a.gather, "run", plan, "--cycles", str(a.cycles), "--seed", seed, "--out",
                             os.path.join(tmp, "one")])
            m = re.search(r"run (\d+) ms for (\d+) s of mission", out)
            one.append(float(m.group(2)) * 1000.0 / float(m.group(1)))
            one_wall.append(float(m.group(2)) / wall)
            for f in os.listdir(tmp):
                if f.startswith("mem."):
                    os.remove(os.path.join(tmp, f))
            out, wall = run([a.gather, "run", plan, "--cycles", str(a.cycles), "--seed", seed, "--out",
                             os.path.join(tmp, "lcm"), "--lcm", "--key-file", key, "--agent-bin", wrapper])
            m = re.search(r"run (\d+) ms for (\d+) s of mission", out)
            lcm.append(float(m.group(2)) * 1000.0 / float(m.group(1)))
            lcm_wall.append(float(m.group(2)) / wall)
            m = re.search(r"= (\d+) messages/s", out)
            rates.append(float(m.group(1)))
            m = re.search(r"per tick ([\d.]+) ms of wall: publishing the tick ([\d.]+) ms, the OC's inbox ([\d.]+) ms, "
                          r"its role ([\d.]+) ms, waiting for the agents' replies ([\d.]+) ms \(their control steps: "
                          r"([\d.]+) ms", out)
            ticks.append([float(x) for x in m.groups()])
            mem = sorted(int(open(os.path.join(tmp, f)).read().split()[-1]) for f in os.listdir(tmp)
                         if f.startswith("mem."))
            mem_med.append(mem[len(mem) // 2] / 1024.0)
            mem_max.append(mem[-1] / 1024.0)
        per = [med([t[i] for t in ticks]) for i in range(6)]
        rows.append((config, one, one_wall, lcm, lcm_wall, rates, per, mem_med, mem_max))

    print("maps/office, 20 agents, %d cycles, %d seeds each; medians (min-max)\n" % (a.cycles, a.runs))
    print("| plan | in one process [x real time] | (whole command) | over LCM, 21 processes [x real time] | "
          "(whole command) | radio messages/s | agent peak RSS median / max [MB] |")
    print("|---|---|---|---|---|---|---|")
    for config, one, one_wall, lcm, lcm_wall, rates, per, mem_med, mem_max in rows:
        print("| %s | %.0f (%.0f-%.0f) | %.0f | %.0f (%.0f-%.0f) | %.0f | %.0f | %.1f / %.1f |" % (
            config, med(one), min(one), max(one), med(one_wall), med(lcm), min(lcm), max(lcm), med(lcm_wall),
            med(rates), med(mem_med), max(mem_max)))
    print("\nWhere a tick's wall time goes over LCM (medians over the runs) [ms]:\n")
    print("| plan | a tick | publishing the tick | the OC's inbox | the OC's role | waiting for the 20 replies | "
          "(the agents' control steps, CPU summed) |")
    print("|---|---|---|---|---|---|---|")
    for config, *_, per, mem_med, mem_max in rows:
        print("| %s | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f |" % (config, *per))
    return 0


if __name__ == "__main__":
    sys.exit(main())
