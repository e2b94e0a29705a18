#!/usr/bin/env python3
"""The fault benchmark of the agent runtime (`make bench-faults` ->
docs/faults_bench.md).

maps/office, pap:4 (with the collector groups as grown, `--association
off`: all four collectors serve workers, so a collector's death matters)
and bap:0, 10 cycles, SEEDS seeds, every role in one process (`gather run`;
the same run as over LCM, byte for byte: tests/e2e/runtime_e2e.py checks
it with a kill). For each seed:
  - fault-free;
  - 20% message loss;
  - 20% loss and one agent killed at 35% of the mission (10 cycles: one
    kill per 10 cycles), for each kind of agent the plan has: a worker of
    the OC, a collector, a worker of a collector (which one: by the seed,
    among the agents of that kind); with the repair `merge` and `none`.
Reports delivered goals against the fault-free run of the same seed, goals
lost with an agent, expired, goals declared lost and recovered later, when
the OC declared the dead agent (after the kill), any agent declared dead
that was not killed (false declarations), and checks the targets.

  python3 tools/fault_bench.py [--seeds 5] [--out docs/faults_bench.md]
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile
import time

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
SCENARIO = os.path.join(REPO, "maps", "office.scenario.yaml")
CONFIGS = [("pap:4", "off"), ("bap:0", "on")]
CYCLES = 10
KILL_AT = 0.35  # of the mission (cycles x period)


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit("fault_bench: %s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr[-800:]))
    return p.stdout


def plan_info(plan_dir):
    """(period [s], {kind: [agent ids]}) from plan.yaml."""
    period, kinds = None, {"oc_worker": [], "collector": [], "collector_worker": []}
    for line in open(os.path.join(plan_dir, "plan.yaml")):
        s = line.strip()
        if s.startswith("cycle_period_s:"):
            period = float(s.split(":")[1])
        if s.startswith("- {id:") and "role:" in s:
            f = dict(kv.split(": ") for kv in s[3:-1].split(", "))
            kind = "collector" if f["role"] == "collector" else ("oc_worker" if f["collector"] == "-1" else "collector_worker")
            kinds[kind].append(int(f["id"]))
    return period, kinds


def one(gather, plan_dir, out, seed, loss=0.0, kill=None, repair="merge"):
    cmd = [gather, "run", plan_dir, "--out", out, "--cycles", str(CYCLES), "--seed", str(seed), "--seeds", "1",
           "--loss", str(loss), "--loss-seed", str(seed), "--repair", repair]
    if kill:
        cmd += ["--kill", "%d@%.3f" % kill]
    run(cmd)
    s = list(csv.DictReader(open(os.path.join(out, "summary.csv"))))[0]
    faults = list(csv.DictReader(open(os.path.join(out, "faults.csv"))))
    requested = sum(1 for _ in open(os.path.join(out, "goals.csv"))) - 1
    r = {k: int(s[k]) for k in ("delivered", "expired", "dropped_overflow", "lost_with_agent")}
    r["requested"] = requested
    r["accounted"] = sum(r[k] for k in ("delivered", "expired", "dropped_overflow", "lost_with_agent"))
    r["recovered"] = int(faults[0]["recovered"]) if faults else 0
    r["declared"] = [(int(f["agent"]), float(f["killed_at"]), float(f["declared_at"])) for f in faults]
    return r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--out", default=os.path.join(REPO, "docs", "faults_bench.md"))
    ap.add_argument("--gather", default=os.path.join(REPO, "catkin_ws", "devel", "lib", "gather_core", "gather"))
    a = ap.parse_args()
    t0 = time.time()
    work = tempfile.mkdtemp(prefix="fault_bench_")
    lines, failures = [], []
    for config, association in CONFIGS:
        plan_dir = os.path.join(work, config.replace(":", ""))
        run([a.gather, "plan", SCENARIO, "--out", plan_dir, "--config", config, "--association", association])
        period, kinds = plan_info(plan_dir)
        cases = [("20% loss", 0.2, None, "merge")]
        for kind in ("oc_worker", "collector", "collector_worker"):
            if kinds[kind]:
                cases.append(("20%% loss, a %s killed" % kind.replace("_", " "), 0.2, kind, "merge"))
                if kind != "collector":  # a dead collector's workers move to the OC whatever the repair mode
                    cases.append(("20%% loss, a %s killed, repair none" % kind.replace("_", " "), 0.2, kind, "none"))
        base = {}
        for seed in range(1, a.seeds + 1):
            base[seed] = one(a.gather, plan_dir, os.path.join(work, "base"), seed)
        lines.append("### %s (association %s): period %.1f s, %d collectors, %d workers of the OC, %d of collectors\n"
                     % (config, association, period, len(kinds["collector"]), len(kinds["oc_worker"]),
                        len(kinds["collector_worker"])))
        lines.append("| case | delivered / fault-free | min over seeds | lost with agent | expired | recovered | "
                     "declared dead after the kill [s] | false declarations | unaccounted |")
        lines.append("|---|---|---|---|---|---|---|---|---|")
        fb = sum(base[s]["delivered"] for s in base)
        lines.append("| fault-free | %d / %d | | %d | %d | | | %d | %d |"
                     % (fb, fb, sum(base[s]["lost_with_agent"] for s in base), sum(base[s]["expired"] for s in base),
                        sum(len(base[s]["declared"]) for s in base), sum(base[s]["requested"] - base[s]["accounted"] for s in base)))
        for name, loss, kind, repair in cases:
            rows = []
            for seed in range(1, a.seeds + 1):
                kill = None
                if kind:
                    ids = kinds[kind]
                    kill = (ids[(seed - 1) % len(ids)], KILL_AT * CYCLES * period)
                r = one(a.gather, plan_dir, os.path.join(work, "case"), seed, loss, kill, repair)
                r["kill"] = kill
                rows.append((seed, r))
            delivered = sum(r["delivered"] for _, r in rows)
            worst = min(r["delivered"] / max(1, base[s]["delivered"]) for s, r in rows)
            delays, false = [], 0
            for _, r in rows:
                for agent, killed_at, declared_at in r["declared"]:
                    if killed_at < 0 and declared_at >= 0:
                        false += 1
                    elif declared_at >= 0:
                        delays.append(declared_at - killed_at)
            unaccounted = sum(r["requested"] - r["accounted"] for _, r in rows)
            lines.append("| %s | %d / %d = %.1f%% | %.1f%% | %d | %d | %d | %s | %d | %d |"
                         % (name, delivered, fb, 100.0 * delivered / fb, 100.0 * worst,
                            sum(r["lost_with_agent"] for _, r in rows), sum(r["expired"] for _, r in rows),
                            sum(r["recovered"] for _, r in rows),
                            ("%.0f-%.0f" % (min(delays), max(delays))) if delays else "-", false, unaccounted))
            target = 0.98 if kind is None else 0.90
            if repair == "merge" and worst < target:
                failures.append("%s %s: %.1f%% of the fault-free delivered goals on its worst seed (target %.0f%%)"
                                % (config, name, 100 * worst, 100 * target))
            if false or unaccounted:
                failures.append("%s %s: %d false declarations, %d goals unaccounted" % (config, name, false, unaccounted))
            if kind and repair == "merge" and not delays:
                failures.append("%s %s: the killed agent was never declared dead" % (config, name))
        # Crash and restart: an agent's process SIGKILLed while it carries
        # data and started again at once from its journal (--restart).
        lines.append("")
        lines.append("| crash and restart (20% loss), the agent carrying data | seeds (with a time it carried data) | goals it "
                     "carried at the crash | measured goals delivered | delivered / fault-free (those seeds) | declared dead |")
        lines.append("|---|---|---|---|---|---|")
        for kind in ("oc_worker", "collector", "collector_worker"):
            if not kinds[kind]:
                continue
            carried_total, measured_total, delivered_measured, delivered, declared, n, fault_free = 0, 0, 0, 0, 0, 0, 0
            for seed in range(1, a.seeds + 1):
                pick = None
                ids = kinds[kind][(seed - 1) % len(kinds[kind]):] + kinds[kind][:(seed - 1) % len(kinds[kind])]
                for agent in ids:
                    for frac in (0.2, 0.3, 0.4, 0.5, 0.6, 0.7):
                        out = os.path.join(work, "restart")
                        cmd = [a.gather, "run", plan_dir, "--out", out, "--cycles", str(CYCLES), "--seed", str(seed),
                               "--loss", "0.2", "--loss-seed", str(seed), "--restart",
                               "%d@%.1f" % (agent, frac * CYCLES * period)]
                        text = run(cmd)
                        m = re.search(r"\((\d+) measured goals carried", text)
                        if m and int(m.group(1)) > 0:
                            pick = int(m.group(1))
                            break
                    if pick:
                        break
                if not pick:
                    continue
                n += 1
                fault_free += base[seed]["delivered"]
                carried_total += pick
                goals = list(csv.DictReader(open(os.path.join(out, "goals.csv"))))
                measured = [g for g in goals if float(g["measured_at"]) >= 0]
                measured_total += len(measured)
                delivered_measured += sum(g["state"] == "delivered" for g in measured)
                delivered += sum(g["state"] == "delivered" for g in goals)
                declared += len([f for f in csv.DictReader(open(os.path.join(out, "faults.csv"))) if float(f["declared_at"]) >= 0])
            if n == 0:
                continue
            lines.append("| a %s | %d | %d | %d / %d | %.1f%% | %d |" % (kind.replace("_", " "), n, carried_total,
                         delivered_measured, measured_total, 100.0 * delivered / fault_free, declared))
            if delivered_measured != measured_total or declared:
                failures.append("%s restart of a %s: %d of %d measured goals delivered, %d declared dead"
                                % (config, kind, delivered_measured, measured_total, declared))
        lines.append("")
    with open(a.out, "w") as f:
        f.write("""# Faults: message loss and dead agents, measured

Written by `make bench-faults` (tools/fault_bench.py): maps/office, %d cycles, seeds 1-%d, every role in one
process (`gather run`; over LCM it is the same run, byte for byte: tests/e2e/runtime_e2e.py checks that with a
kill). Loss is injected after the range gate (`--loss 0.2 --loss-seed SEED`). A kill ends one agent at %.0f%% of
the mission (`--kill ID@T`), the agent chosen by the seed among those of its kind. "delivered / fault-free" sums
the delivered goals over the seeds against the fault-free runs of the same seeds; "min over seeds" is the worst
seed's ratio. "recovered": goals the OC had declared lost with the dead agent that a survivor delivered or
reported later. "unaccounted": goals requested but neither delivered, expired, dropped_overflow nor
lost_with_agent (must be 0; every run also checks conservation at every cycle's end and, at its end, that
every goal declared lost was held by a dead agent or was a dead worker's own). "crash and restart": the
agent's process is killed while it carries data (the first of several times at which it does, found by
running) and started again at once from its journal (`--restart ID@T`): "goals it carried at the crash" comes
from its journal, and every goal measured in the run must be delivered (the OC keeps one copy per goal).
How the OC notices a dead agent and repairs the plan: docs/faults.md.

""" % (CYCLES, a.seeds, 100 * KILL_AT))
        f.write("\n".join(lines))
        f.write("\nTargets (issue 13): 20%% loss >= 98%% of the fault-free delivered goals, a kill >= 90%% (worst "
                "seed, repair merge), 0 false declarations, 0 unaccounted; a crash and restart of an agent carrying "
                "data: every measured goal delivered, none declared dead: %s.\n\nRun time: %.0f s.\n"
                % ("met" if not failures else "NOT met: " + "; ".join(failures), time.time() - t0))
    print(open(a.out).read())
    if failures:
        sys.exit("fault_bench: " + "; ".join(failures))


if __name__ == "__main__":
    main()
