#!/usr/bin/python3
"""Plans and simulates every scenario in maps/ and ../shared/maps/ipa/ and
writes docs/scenarios.md: per scenario the planning grid, the sweep's wall
time (median of --repeat runs) and stage times, the best configuration by
estimate (E) and by simulation (R), the estimate error |E - R| / R of every
configuration, and whether the seed's conclusions hold in E and in R.

  tools/scenario_report.py [--gather BIN] [--out docs/scenarios.md] [--results DIR]
                           [--repeat 3] [--seeds 5] [--cycles C] [SCENARIO...]

Per scenario NAME it runs
  gather plan SCENARIO --out RESULTS/NAME/plan          (--repeat times)
  gather sim RESULTS/NAME/plan --all-configs --seeds K --out RESULTS/NAME/sim
and keeps their outputs (Fig. 2, Fig. 3 with the R bands, Fig. 4) there.
Real utilities are normalised per seed over the 27 configurations, as the
estimates are over the configurations, then averaged over the seeds.
"""
import argparse
import csv
import glob
import os
import re
import statistics
import subprocess
import sys
import time

import yaml

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))


def die(msg):
    sys.exit("scenario_report: " + msg)


def run(cmd):
    t0 = time.monotonic()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        die("%s failed: %s" % (" ".join(cmd), p.stderr.strip()))
    return p.stdout, time.monotonic() - t0


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def utilities(rows, refresh_key, goals_key, alpha, beta):
    """U of each row, min-max normalised over `rows` (docs/planner.md)."""
    ts = [r[refresh_key] for r in rows]
    ns = [r[goals_key] for r in rows]
    tmin, tmax, nmin, nmax = min(ts), max(ts), min(ns), max(ns)
    t_var = tmax - tmin > 1e-6 * max(1.0, abs(tmax))
    n_var = nmax - nmin > 1e-6 * max(1.0, abs(nmax))
    out = []
    for t, n in zip(ts, ns):
        tn = (t - tmin) / (tmax - tmin) if t_var else 0.0
        nn = (n - nmin) / (nmax - nmin) if n_var else 0.0
        out.append((alpha * (1 - tn) + beta * nn) / (alpha + beta))
    return out


def conclusions(configs, ukey):
    """(collectors beat none, best N_c in 1-4, BAP/PAP >= RAP) on utility `ukey`.
    A configuration uses collectors when some worker delivers to one: one
    whose collectors all stay at the OC (the association gave every segment
    to the OC) is a team without collectors, and fewer workers."""
    best = max(configs, key=lambda c: c[ukey])
    uses = lambda c: c["active"] > 0
    u0 = max((c[ukey] for c in configs if not uses(c)), default=None)
    u1 = max((c[ukey] for c in configs if uses(c)), default=None)
    per = {}
    for c in configs:
        per[c["method"]] = max(per.get(c["method"], -1.0), c[ukey])
    bp = max(per.get("bap", -1.0), per.get("pap", -1.0))
    return (u0 is not None and u1 is not None and u1 > u0, uses(best) and 1 <= best["active"] <= 4,
            "rap" not in per or bp >= per["rap"]), best


METRICS = (("latency", "est_refresh_s", "refresh_mean_s"), ("interval", "est_interval_s", "interval_mean_s"))


def report_scenario(a, sc, name=None, out=None):
    """Plans and simulates scenario `sc` into `out` (a.results/NAME); returns
    its configurations with E and R of both refresh metrics and of goals, the
    utilities on each metric, and the seed's conclusions per metric."""
    name = name or os.path.basename(sc).replace(".scenario.yaml", "")
    with open(sc) as f:
        spec = yaml.safe_load(f) or {}
    planner = spec.get("planner") or {}
    alpha = 0.5 if planner.get("alpha") is None else float(planner["alpha"])  # gather's defaults
    beta = 0.5 if planner.get("beta") is None else float(planner["beta"])
    out = out or os.path.join(a.results, name)
    plan_dir, sim_dir = os.path.join(out, "plan"), os.path.join(out, "sim")
    reuse = getattr(a, "reuse", False) and all(
        os.path.isfile(p) for p in (os.path.join(plan_dir, "report.csv"), os.path.join(sim_dir, "summary.csv")))
    if reuse:  # the outputs of an earlier run (regime_report --reuse): no timings
        sweep_ms, stages, plan_wall, grid, sim_wall, slowest = None, None, None, None, None, None
    else:
        plans = []
        for _ in range(a.repeat):
            stdout, wall = run([a.gather, "plan", sc, "--out", plan_dir])
            m = re.search(r"stages \[ms, summed over configurations\]: (.*); sweep wall (\d+) ms", stdout)
            if not m:
                die("no stage times in the output of gather plan " + sc)
            grid = re.search(r"planning grid: (\S+) cells of (\S+) m", stdout)
            plans.append((int(m.group(2)), m.group(1), wall, grid.group(1) + " at " + grid.group(2) + " m" if grid else None))
        plans.sort(key=lambda p: p[0])
        sweep_ms, stages, plan_wall, grid = plans[len(plans) // 2]
        if grid is None:
            grid = "the map's own grid"
        sim_cmd = [a.gather, "sim", plan_dir, "--all-configs", "--seeds", str(a.seeds), "--out", sim_dir]
        if a.cycles:
            sim_cmd += ["--cycles", str(a.cycles)]
        stdout, sim_wall = run(sim_cmd)
        slowest = re.search(r"slowest run (\d+)x", stdout)

    est = {(r["method"], int(r["collectors"])): r for r in read_csv(os.path.join(plan_dir, "report.csv"))}
    rows = read_csv(os.path.join(sim_dir, "summary.csv"))
    if not est or not rows:
        die("%s: empty report.csv or summary.csv in %s" % (name, out))
    for r in rows:
        for k in ("refresh_mean_s", "interval_mean_s", "goals_per_cycle", "speedup"):
            r[k] = float(r[k])
    est_rows = list(est.values())
    for r in est_rows:
        for k in ("est_refresh_s", "est_interval_s", "est_goals", "oc_workers"):
            r[k] = float(r[k])
    speedup = statistics.median(r["speedup"] for r in rows)
    by_seed = {}
    for r in rows:
        by_seed.setdefault(r["seed"], []).append(r)
    for metric, ekey, rkey in METRICS:
        for r, u in zip(est_rows, utilities(est_rows, ekey, "est_goals", alpha, beta)):
            r["u_" + metric] = u
        for seed_rows in by_seed.values():
            for r, u in zip(seed_rows, utilities(seed_rows, rkey, "goals_per_cycle", alpha, beta)):
                r["u_" + metric] = u
    configs = []
    for key, e in est.items():
        mine = [r for r in rows if (r["method"], int(r["collectors"])) == key]
        if not mine:
            die("%s: no simulation of %s N_c=%d" % (name, key[0], key[1]))
        c = dict(method=key[0], nc=key[1], oc_workers=int(e["oc_workers"]), active=int(e["active_collectors"]),
                 e_n=e["est_goals"])
        rg = [r["goals_per_cycle"] for r in mine]
        c.update(r_n=statistics.mean(rg), r_n_lo=min(rg), r_n_hi=max(rg))
        for metric, ekey, rkey in METRICS:
            rt = [r[rkey] for r in mine]
            c["e_" + metric] = e[ekey]
            c.update({"r_" + metric: statistics.mean(rt), "r_%s_lo" % metric: min(rt), "r_%s_hi" % metric: max(rt)})
            c["e_u_" + metric] = e["u_" + metric]
            c["r_u_" + metric] = statistics.mean(r["u_" + metric] for r in mine)
        configs.append(c)
    order = {"bap": 0, "pap": 1, "rap": 2}
    configs.sort(key=lambda c: (order.get(c["method"], 9), c["nc"]))
    err = lambda e, r: abs(e - r) / r if r > 0 else float("nan")
    for c in configs:
        for metric, _, _ in METRICS:
            c["err_" + metric] = err(c["e_" + metric], c["r_" + metric])
        c["err_n"] = err(c["e_n"], c["r_n"])
    rep = dict(name=name, grid=grid, sweep_ms=sweep_ms, stages=stages, plan_wall=plan_wall, sim_wall=sim_wall,
               slowest=int(slowest.group(1)) if slowest else None, speedup=speedup, configs=configs)
    for metric, _, _ in METRICS:
        for side in ("e", "r"):
            rep["%s_concl_%s" % (side, metric)], rep["%s_best_%s" % (side, metric)] = conclusions(
                configs, "%s_u_%s" % (side, metric))
    return rep


def mean_err(r, what):
    """Mean |E - R| / R over a scenario's configurations of 'latency', 'interval' or 'n' (goals)."""
    return statistics.mean(c["err_" + what] for c in r["configs"])


def fmt_best(c, u):
    return "%s %d (U %.2f)" % (c["method"].upper(), c["nc"], c[u])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gather", default=os.path.join(REPO, "catkin_ws/devel/lib/gather_core/gather"))
    ap.add_argument("--out", default=os.path.join(REPO, "docs/scenarios.md"))
    ap.add_argument("--results", default=os.path.join(REPO, "results/scenarios"))
    ap.add_argument("--repeat", type=int, default=3, help="sweeps per scenario; the median wall time is reported")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--cycles", type=int, default=0, help="0 = the scenario's mission.cycles")
    ap.add_argument("scenarios", nargs="*")
    a = ap.parse_args()
    if a.repeat < 1 or a.seeds < 1 or a.cycles < 0:
        die("--repeat and --seeds must be >= 1, --cycles >= 0")
    if not os.access(a.gather, os.X_OK):
        die("no gather binary at %s (make build)" % a.gather)
    scenarios = a.scenarios or (sorted(glob.glob(os.path.join(REPO, "maps/*.scenario.yaml"))) +
                                sorted(glob.glob(os.path.join(REPO, "../shared/maps/ipa/*.scenario.yaml"))))
    load = open("/proc/loadavg").read().split()[0]
    reports = []
    for sc in scenarios:
        r = report_scenario(a, sc)
        reports.append(r)
        print("%-16s sweep %.2f s  best E/R latency %s / %s, interval %s / %s  mean |E-R|/R latency %.0f%% "
              "interval %.0f%% goals %.0f%%  sim %.0f s" % (
                  r["name"], r["sweep_ms"] / 1000.0, fmt_best(r["e_best_latency"], "e_u_latency"),
                  fmt_best(r["r_best_latency"], "r_u_latency"), fmt_best(r["e_best_interval"], "e_u_interval"),
                  fmt_best(r["r_best_interval"], "r_u_interval"), 100 * mean_err(r, "latency"),
                  100 * mean_err(r, "interval"), 100 * mean_err(r, "n"), r["sim_wall"]), flush=True)

    yn = lambda b: "yes" if b else "**no**"
    L = []
    L.append("# Scenarios: estimated and simulated plans\n")
    L.append("Produced by `make scenario-report` (`tools/scenario_report.py`) on this 2-core machine (load average "
             "%s when it started). For every scenario: `gather plan SCENARIO` %d times (27 configurations: "
             "BAP/PAP/RAP x N_c = 0..8, 20 agents, 2 threads; the median sweep wall time is shown), then "
             "`gather sim PLAN --all-configs --seeds %d` (every configuration, %d seeds, the scenario's cycles). "
             "E = the planner's estimate (docs/planner.md), R = the simulator's mean over the seeds "
             "(docs/simulator.md), [lo–hi] its range. Two refresh metrics (docs/planner.md, \"Two refresh "
             "metrics\"): latency (request to delivery, per goal) and interval (per area, the time between "
             "consecutive deliveries of its data). The utility U is computed on each, in E over the 27 "
             "configurations and in R per seed over them (then averaged). OCw = the workers the association "
             "step sends to the OC, active = the collectors left with workers; a configuration counts as using "
             "collectors when some are active (the best N_c of the seed's conclusion is the active count). Nothing was tuned to make the seed's conclusions hold.\n"
             % (load, a.repeat, a.seeds, a.seeds))
    L.append("| scenario | planning grid | sweep [s] | best by E / R, latency | best by E / R, interval | "
             "mean \\|E−R\\|/R latency / interval / goals | collectors beat none, latency E / R, interval E / R | "
             "best N_c in 1-4, latency E / R, interval E / R | BAP/PAP ≥ RAP, latency E / R, interval E / R |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    for r in reports:
        cells = []
        for i in range(3):
            cells.append(" / ".join(yn(r["%s_concl_%s" % (side, m)][i]) for m in ("latency", "interval") for side in ("e", "r")))
        L.append("| %s | %s | %.2f | %s / %s | %s / %s | %.0f%% / %.0f%% / %.0f%% | %s | %s | %s |" % (
            r["name"], r["grid"], r["sweep_ms"] / 1000.0, fmt_best(r["e_best_latency"], "e_u_latency"),
            fmt_best(r["r_best_latency"], "r_u_latency"), fmt_best(r["e_best_interval"], "e_u_interval"),
            fmt_best(r["r_best_interval"], "r_u_interval"), 100 * mean_err(r, "latency"), 100 * mean_err(r, "interval"),
            100 * mean_err(r, "n"), cells[0], cells[1], cells[2]))
    n = len(reports)
    L.append("")
    for i, what in enumerate(("collectors beat no collectors", "the best N_c lies in 1-4", "BAP or PAP at least as good as RAP")):
        L.append("- %s: latency E %d, R %d; interval E %d, R %d (of %d scenarios)." % (
            what, sum(r["e_concl_latency"][i] for r in reports), sum(r["r_concl_latency"][i] for r in reports),
            sum(r["e_concl_interval"][i] for r in reports), sum(r["r_concl_interval"][i] for r in reports), n))
    within = [r["name"] for r in reports
              if all(e == e and e <= 0.10 for e in (mean_err(r, "latency"), mean_err(r, "interval"), mean_err(r, "n")))]
    L.append("- mean |E−R|/R within 10%% for latency, interval and goals: %d of %d scenarios%s." % (
        len(within), n, (" (" + ", ".join(sorted(set(r["name"] for r in reports) - set(within))) + " outside)")
        if len(within) < n else ""))
    L.append("")
    for r in reports:
        L.append("\n## %s\n" % r["name"])
        L.append("Planning grid: %s. Sweep %.2f s wall (median), stages [ms, summed over configurations]: %s. "
                 "`gather plan` command %.1f s; `gather sim --all-configs` %.0f s wall; one run of the scenario's cycles: "
                 "median %.0fx real time, slowest %sx (summary.csv, %d runs). "
                 "Figures: `results/scenarios/%s/plan/` (Fig. 2, Fig. 3 E) and `results/scenarios/%s/sim/` (Fig. 3 with "
                 "R bands, Fig. 4).\n" % (r["grid"], r["sweep_ms"] / 1000.0, r["stages"], r["plan_wall"], r["sim_wall"],
                                          r["speedup"], r["slowest"], len(r["configs"]) * a.seeds, r["name"],
                                          r["name"]))
        L.append("| method | N_c | active | OCw | E latency [s] | R latency [s] [lo–hi] | err | E interval [s] | R interval [s] [lo–hi] "
                 "| err | E goals | R goals [lo–hi] | err | U latency E / R | U interval E / R |")
        L.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        for c in r["configs"]:
            def u(m):
                me = " **E**" if c is r["e_best_" + m] else ""
                mr = " **R**" if c is r["r_best_" + m] else ""
                return "%.3f%s / %.3f%s" % (c["e_u_" + m], me, c["r_u_" + m], mr)
            L.append("| %s | %d | %d | %d | %.1f | %.1f [%.1f–%.1f] | %.0f%% | %.1f | %.1f [%.1f–%.1f] | %.0f%% | %.2f | "
                     "%.2f [%.2f–%.2f] | %.0f%% | %s | %s |" % (
                         c["method"].upper(), c["nc"], c["active"], c["oc_workers"], c["e_latency"], c["r_latency"],
                         c["r_latency_lo"], c["r_latency_hi"], 100 * c["err_latency"], c["e_interval"], c["r_interval"],
                         c["r_interval_lo"], c["r_interval_hi"], 100 * c["err_interval"], c["e_n"], c["r_n"],
                         c["r_n_lo"], c["r_n_hi"], 100 * c["err_n"], u("latency"), u("interval")))
    with open(a.out, "w") as f:
        f.write("\n".join(L) + "\n")
    print("wrote %s" % a.out)


if __name__ == "__main__":
    main()
