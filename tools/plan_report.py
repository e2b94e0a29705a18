#!/usr/bin/env python3
"""Runs `gather plan` on every scenario in maps/ and ../shared/maps/ipa/ and
writes docs/plans.md: the chosen configuration per scenario, the sweep's wall
time and stage times, and whether the seed's conclusions hold in the
estimates (collectors beat no collectors; the best N_c lies in 1-4; BAP or PAP
best, RAP worst).

  tools/plan_report.py [--gather BIN] [--out docs/plans.md] [--results DIR] [SCENARIO...]
"""
import argparse
import csv
import glob
import os
import re
import subprocess
import sys
import time

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))


def run(gather, scenario, out):
    t0 = time.monotonic()
    p = subprocess.run([gather, "plan", scenario, "--out", out], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       text=True)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        sys.exit("plan_report: gather plan %s failed: %s" % (scenario, p.stderr.strip()))
    stages = re.search(r"stages \[ms, summed over configurations\]: (.*); sweep wall (\d+) ms", p.stdout)
    with open(os.path.join(out, "report.csv")) as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("collectors", "workers"):
            r[k] = int(r[k])
        for k in ("est_refresh_s", "est_goals", "utility", "plan_ms"):
            r[k] = float(r[k])
    return rows, stages.group(1) if stages else "?", int(stages.group(2)) if stages else -1, wall


def verdicts(rows):
    best = max(rows, key=lambda r: r["utility"])
    u0 = max((r["utility"] for r in rows if r["collectors"] == 0), default=None)
    u1 = max((r["utility"] for r in rows if r["collectors"] >= 1), default=None)
    per_method = {}
    for r in rows:
        per_method[r["method"]] = max(per_method.get(r["method"], -1), r["utility"])
    collectors_win = u0 is not None and u1 is not None and u1 > u0
    nc_ok = 1 <= best["collectors"] <= 4
    ranked = sorted(per_method, key=lambda m: -per_method[m])
    bap_pap_best = ranked[0] in ("bap", "pap")
    rap_worst = ranked[-1] == "rap"
    return best, collectors_win, nc_ok, bap_pap_best, rap_worst, per_method


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gather", default=os.path.join(REPO, "catkin_ws/devel/lib/gather_core/gather"))
    ap.add_argument("--out", default=os.path.join(REPO, "docs/plans.md"))
    ap.add_argument("--results", default=os.path.join(REPO, "results/plans"))
    ap.add_argument("--repeat", type=int, default=3, help="sweeps per scenario; the median wall time is reported")
    ap.add_argument("scenarios", nargs="*")
    a = ap.parse_args()
    scenarios = a.scenarios or (sorted(glob.glob(os.path.join(REPO, "maps/*.scenario.yaml"))) +
                                sorted(glob.glob(os.path.join(REPO, "../shared/maps/ipa/*.scenario.yaml"))))
    lines = []
    summary = []
    load = open("/proc/loadavg").read().split()[0]
    for sc in scenarios:
        name = os.path.basename(sc).replace(".scenario.yaml", "")
        runs = [run(a.gather, sc, os.path.join(a.results, name)) for _ in range(max(1, a.repeat))]
        runs.sort(key=lambda r: r[2])
        rows, stages, sweep_ms, wall = runs[len(runs) // 2]  # the run with the median sweep time
        best, cw, nc_ok, bp, rw, per_method = verdicts(rows)
        yn = lambda b: "yes" if b else "**no**"
        summary.append("| %s | %s, N_c = %d | %.0f | %.1f | %.3f | %s | %s | %s | %s | %.2f | %.2f |" % (
            name, best["method"].upper(), best["collectors"], best["est_refresh_s"], best["est_goals"],
            best["utility"], yn(cw), yn(nc_ok), yn(bp), yn(rw), sweep_ms / 1000.0, wall))
        lines.append("### %s\n" % name)
        lines.append("Stages (ms, summed over configurations): %s. Best U per method: %s.\n" % (
            stages, ", ".join("%s %.3f" % (m.upper(), u) for m, u in sorted(per_method.items()))))
        lines.append("| method | N_c | N_w | est. refresh [s] | est. goals | U | plan [ms] |")
        lines.append("|---|---|---|---|---|---|---|")
        for r in rows:
            mark = " **best**" if r is best else ""
            lines.append("| %s | %d | %d | %.1f | %.2f | %.3f%s | %.0f |" % (
                r["method"].upper(), r["collectors"], r["workers"], r["est_refresh_s"], r["est_goals"],
                r["utility"], mark, r["plan_ms"]))
        lines.append("")
        print("%-18s best %s Nc=%d U=%.3f sweep %.2f s (wall %.2f s)" % (
            name, best["method"], best["collectors"], best["utility"], sweep_ms / 1000.0, wall), flush=True)

    with open(a.out, "w") as f:
        f.write("# Deployment plans: estimated sweep per scenario\n\n")
        f.write("Produced by `make plan-report` (`tools/plan_report.py`), which runs "
                "`gather plan SCENARIO --out results/plans/NAME` %d times on every scenario (20 agents, N_c = 0..8, "
                "BAP/PAP/RAP: 27 configurations, 2 threads) on this machine and shows the run with the median "
                "sweep time (load average %s when it started). Model: docs/planner.md. "
                "These are estimates (E); the simulator measures the real values (R). "
                "Why the seed's conclusions hold or not here: docs/planner.md, 'What the estimates say, and why'.\n\n" % (a.repeat, load))
        f.write("| scenario | best | refresh [s] | goals | U | collectors beat none | best N_c in 1-4 | "
                "BAP or PAP best | RAP worst | sweep [s] | command wall [s] |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|---|\n")
        f.write("\n".join(summary) + "\n\n")
        f.write("\n".join(lines) + "\n")
    print("wrote %s" % a.out)


if __name__ == "__main__":
    main()
