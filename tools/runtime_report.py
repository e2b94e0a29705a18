#!/usr/bin/env python3
"""The agent runtime against the analytic simulator, and over LCM against
one process (`make runtime-report` -> docs/runtime_equivalence.md).

For maps/office and ../shared/maps/ipa/office_a, configurations bap:0,
pap:2 and pap:4 as the planner decides them, and pap:4 with the collector
groups as grown (`--association off`, all four collectors busy): the mean refresh time and goals per cycle over SEEDS seeds
of 10 cycles from `gather sim` (the analytic simulator) and from `gather
run` (every agent's role in one process), their relative difference, and
whether `gather run --lcm` (one process per agent over LCM) gives
byte-identical goals.csv and cycles.csv for the first seed.

  tools/netns-run python3 tools/runtime_report.py [--seeds 5] [--out docs/runtime_equivalence.md]
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
SCENARIOS = [("maps/office", os.path.join(REPO, "maps", "office.scenario.yaml")),
             ("ipa/office_a", os.path.join(REPO, "..", "shared", "maps", "ipa", "office_a.scenario.yaml"))]
# (configuration, association): the planner's decision, and pap:4 with the
# grown groups (every far segment served by a collector: all four busy).
CONFIGS = [("bap:0", "on"), ("pap:2", "on"), ("pap:4", "on"), ("pap:4", "off")]


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit("runtime_report: %s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr[-800:]))
    return p.stdout


def means(summary_csv):
    rows = list(csv.DictReader(open(summary_csv)))
    n = len(rows)
    return (sum(float(r["refresh_mean_s"]) for r in rows) / n, sum(float(r["goals_per_cycle"]) for r in rows) / n,
            float(rows[0]["est_refresh_s"]), float(rows[0]["est_goals"]))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--out", default=os.path.join(REPO, "docs", "runtime_equivalence.md"))
    ap.add_argument("--gather", default=os.path.join(REPO, "catkin_ws", "devel", "lib", "gather_core", "gather"))
    a = ap.parse_args()
    if os.environ.get("GATHER_NETNS") != "1":
        sys.exit("runtime_report: run me inside tools/netns-run (gather run --lcm sends LCM multicast)")
    tmp = tempfile.mkdtemp(prefix="gather_runtime_report_")
    key = os.path.join(tmp, "fleet.key")  # the runs over LCM sign their traffic (docs/security.md)
    subprocess.run([a.gather, "keygen", key], check=True, stdout=subprocess.DEVNULL)
    lines = []
    worst_r = worst_g = 0.0
    all_identical = True
    for name, scenario in SCENARIOS:
        for config, association in CONFIGS:
            d = os.path.join(tmp, name.replace("/", "_") + "_" + config.replace(":", "") + "_" + association)
            run([a.gather, "plan", scenario, "--config", config, "--association", association, "--out", d + "/plan"])
            run([a.gather, "sim", d + "/plan", "--cycles", "10", "--seeds", str(a.seeds), "--out", d + "/sim"])
            run([a.gather, "run", d + "/plan", "--cycles", "10", "--seeds", str(a.seeds), "--out", d + "/run"])
            run([a.gather, "run", d + "/plan", "--cycles", "10", "--out", d + "/one"])
            run([a.gather, "run", d + "/plan", "--cycles", "10", "--out", d + "/lcm", "--lcm", "--key-file", key])
            identical = all(open(os.path.join(d, "one", f), "rb").read() == open(os.path.join(d, "lcm", f), "rb").read()
                            for f in ("goals.csv", "cycles.csv"))
            all_identical = all_identical and identical
            rs, gs, er, eg = means(os.path.join(d, "sim", "summary.csv"))
            ra, ga, _, _ = means(os.path.join(d, "run", "summary.csv"))
            dr, dg = (ra - rs) / rs * 100.0, (ga - gs) / gs * 100.0
            worst_r, worst_g = max(worst_r, abs(dr)), max(worst_g, abs(dg))
            lines.append("| %s | %s | %.1f | %.1f | %.1f | %+.1f%% | %.2f | %.2f | %.2f | %+.1f%% | %s |" % (
                name, config + ("" if association == "on" else " (association off)"), er, rs, ra, dr, eg, gs, ga, dg, "yes" if identical else "**NO**"))
            print(lines[-1], flush=True)
    with open(a.out, "w") as f:
        f.write("# The agent runtime against the analytic simulator\n\n")
        f.write("Written by `make runtime-report` (`tools/runtime_report.py`); how the two differ and why: "
                "[runtime.md](runtime.md#agents-and-the-analytic-simulator).\n\n")
        f.write("Mean over %d seeds (1..%d) of 10 cycles, 20 agents. E: the planner's estimate; S: the analytic "
                "simulator (`gather sim`); A: the agents, every role in one process (`gather run`, tick 0.1 s). "
                "LCM = 1: `gather run --lcm` (one process per agent over LCM) gave byte-identical goals.csv and "
                "cycles.csv to `gather run` in one process, seed 1.\n\n" % (a.seeds, a.seeds))
        f.write("| scenario | config | refresh E [s] | refresh S [s] | refresh A [s] | A vs S | goals/cycle E | "
                "goals/cycle S | goals/cycle A | A vs S | LCM = 1 |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|---|\n")
        f.write("\n".join(lines) + "\n\n")
        f.write("Largest difference between the agents and the simulator: %.1f%% on the refresh time, %.1f%% on the "
                "goals per cycle (target: 5%%). Over LCM identical to one process: %s.\n" % (
                    worst_r, worst_g, "all" if all_identical else "NOT ALL"))
    print("-> %s (largest |A-S|/S: refresh %.1f%%, goals %.1f%%; LCM identical: %s)" % (
        a.out, worst_r, worst_g, all_identical))
    return 0 if all_identical and worst_r <= 5 and worst_g <= 5 else 1


if __name__ == "__main__":
    sys.exit(main())
