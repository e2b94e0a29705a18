#!/usr/bin/python3
"""Where collectors pay off: sweeps, on a few maps, the OC's coverage radius
(the radio sensitivity), the goals per request and the request period;
plans and simulates every configuration at each grid point, and writes
docs/regimes.md with one figure per map: the best (method, N_c) by estimate
(E) and by simulation (R), under both refresh metrics, with the seed's three
conclusions checked at each point and where the agents' time went.

  tools/regime_report.py [--gather BIN] [--out docs/regimes.md] [--results DIR]
                         [--seeds 2] [--cycles 3] [--sensitivity-db +10,0,-10]
                         [--goals-per-worker 1,10,50] [--periods 1,2] [--reuse] [SCENARIO...]

Per scenario and sensitivity offset it plans bap:0 once to learn the request
period T0 the planner would pick (farthest reachable cell / speed), then per
(goals, period factor f) writes a scenario variant (mission.period = f T0)
and runs `gather plan` and `gather sim --all-configs` on it through
tools/scenario_report.py's report_scenario. Outputs and figures of every
point stay in RESULTS/MAP/POINT/; --reuse reads the plans and simulations
found there instead of running them again (to redraw the figures and the
report).
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
import time

import yaml
from PIL import Image, ImageDraw, ImageFont

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scenario_report as sr  # noqa: E402

REPO = sr.REPO
DEFAULT_MAPS = ["maps/office.scenario.yaml", "maps/campus.scenario.yaml", "../shared/maps/ipa/office_a.scenario.yaml"]


def die(msg):
    sys.exit("regime_report: " + msg)


def floats(text, what):
    try:
        v = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        die("%s: expected numbers separated by commas, got '%s'" % (what, text))
    if not v:
        die("%s: empty" % what)
    return v


def variant(src, dst, sensitivity, goals=None, period=None, cycles=None):
    """Writes a copy of scenario `src` to `dst` with the given changes and
    the map path made absolute."""
    with open(src) as f:
        spec = yaml.safe_load(f)
    spec["map"] = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(src)), spec["map"]))
    spec.setdefault("radio", {})["sensitivity_dbm"] = sensitivity
    mission = spec.setdefault("mission", {})
    if goals is not None:
        mission["goals_per_request"] = goals
    if period is not None:
        mission["period"] = period
    if cycles is not None:
        mission["cycles"] = cycles
    os.makedirs(os.path.dirname(dst), exist_ok=True)
    with open(dst, "w") as f:
        yaml.safe_dump(spec, f, sort_keys=False)


def role_budget(sim_dir, method, nc):
    """Mean fractions (measuring, commuting, waiting) per role of one
    configuration, over its agents and seeds (roles.csv)."""
    acc = {}
    for r in sr.read_csv(os.path.join(sim_dir, "roles.csv")):
        if r["method"] != method or int(r["collectors"]) != nc:
            continue
        m, c, w = float(r["measuring_s"]), float(r["commuting_s"]), float(r["waiting_s"])
        total = m + c + w
        if total > 0:
            acc.setdefault(r["role"], []).append((m / total, c / total, w / total))
    return {role: tuple(statistics.mean(x[i] for x in v) for i in range(3)) for role, v in acc.items()}


def fmt_budget(b, role):
    if role not in b:
        return "–"
    m, c, w = b[role]
    return "%.0f/%.0f/%.0f" % (100 * m, 100 * c, 100 * w)


def point_label(c):
    return "%s %d" % (c["method"].upper(), c["active"]) if c["active"] else "%s 0" % c["method"].upper()


def draw_map_figure(path, title, points, sens, goals, periods):
    """One figure per map: four panels (latency E, latency R, interval E,
    interval R); in each, rows = (period factor, goals per worker), columns
    = coverage; a cell names the best configuration (method and its active
    collectors) and is coloured by the active collectors."""
    try:
        font = ImageFont.truetype("DejaVuSans.ttf", 12)
    except OSError:
        font = ImageFont.load_default()
    cw, ch, left, top, gap = 104, 24, 130, 64, 26
    rows = [(f, g) for f in periods for g in goals]
    pw, ph = left + cw * len(sens), top + ch * len(rows)
    legend_h = 76
    img = Image.new("RGB", (max(2 * pw + gap * 3, 760), 2 * ph + gap * 3 + legend_h + 24), "white")
    d = ImageDraw.Draw(img)
    d.text((gap, 6), title, fill="black", font=font)
    shades = [(225, 225, 225), (198, 235, 197), (141, 211, 141), (65, 171, 93), (35, 132, 67), (0, 90, 50)]
    panels = [("latency", "e", "E"), ("latency", "r", "R"), ("interval", "e", "E"), ("interval", "r", "R")]
    for k, (metric, side, letter) in enumerate(panels):
        ox = gap + (k % 2) * (pw + gap)
        oy = 24 + gap + (k // 2) * (ph + gap)
        d.text((ox, oy), "best by %s, %s refresh" % (letter, metric), fill="black", font=font)
        d.text((ox, oy + 16), "period x T0, goals/worker", fill=(90, 90, 90), font=font)
        for j, s in enumerate(sens):
            cov = points.get((s, goals[0], periods[0]), {}).get("coverage")
            label = "%+g dB" % s + ((" (%.1f%%)" if cov < 1 else " (%.0f%%)") % cov if cov is not None else "")
            d.text((ox + left + j * cw + 4, oy + 40), label, fill="black", font=font)
        for i, (f, g) in enumerate(rows):
            y = oy + top + i * ch
            d.text((ox + 4, y + 5), "%gx T0, %g" % (f, g), fill="black", font=font)
            for j, s in enumerate(sens):
                x = ox + left + j * cw
                p = points.get((s, g, f))
                if p is None:
                    d.rectangle([x, y, x + cw - 2, y + ch - 2], outline=(200, 200, 200))
                    continue
                best = p["report"]["%s_best_%s" % (side, metric)]
                fill = shades[min(best["active"], len(shades) - 1)]
                d.rectangle([x, y, x + cw - 2, y + ch - 2], fill=fill, outline=(150, 150, 150))
                txt_col = "white" if best["active"] >= 3 else "black"
                d.text((x + 6, y + 5), point_label(best), fill=txt_col, font=font)
    ly = 2 * ph + gap * 3 + 30
    d.text((gap, ly), "cell: best method and its active collectors (those left with workers); colour:", fill="black",
           font=font)
    for n, col in enumerate(shades):
        x = gap + n * 120
        d.rectangle([x, ly + 18, x + 18, ly + 32], fill=col, outline=(120, 120, 120))
        d.text((x + 24, ly + 20), "no collectors" if n == 0 else ("%d active" % n if n < 5 else "5+ active"),
               fill="black", font=font)
    d.text((gap, ly + 40), "columns: radio sensitivity offset from the scenario's (coverage share of the reachable "
           "space); T0 = farthest cell / speed", fill=(90, 90, 90), font=font)
    img.save(path)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gather", default=os.path.join(REPO, "catkin_ws/devel/lib/gather_core/gather"))
    ap.add_argument("--out", default=os.path.join(REPO, "docs/regimes.md"))
    ap.add_argument("--results", default=os.path.join(REPO, "results/regimes"))
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--cycles", type=int, default=3)
    ap.add_argument("--sensitivity-db", default="+10,0,-10",
                    help="offsets [dB] added to the scenario's radio.sensitivity_dbm (+ = smaller coverage)")
    ap.add_argument("--goals-per-worker", default="1,10,50", help="goals per request / team.agents")
    ap.add_argument("--periods", default="1,2", help="request period as a factor of T0")
    ap.add_argument("--reuse", action="store_true",
                    help="read the plans and simulations already in --results instead of running them")
    ap.add_argument("scenarios", nargs="*")
    a = ap.parse_args()
    if a.seeds < 1 or a.cycles < 1:
        die("--seeds and --cycles must be >= 1")
    if not os.access(a.gather, os.X_OK):
        die("no gather binary at %s (make build)" % a.gather)
    sens, goals, periods = (floats(a.sensitivity_db, "--sensitivity-db"), floats(a.goals_per_worker, "--goals-per-worker"),
                            floats(a.periods, "--periods"))
    if any(g <= 0 for g in goals) or any(f <= 0 for f in periods):
        die("--goals-per-worker and --periods must be > 0")
    scenarios = a.scenarios or [os.path.join(REPO, m) for m in DEFAULT_MAPS]
    for sc in scenarios:
        if not os.path.isfile(sc):
            die("no scenario file %s" % sc)
    a.repeat = 1  # for report_scenario
    t_start = time.monotonic()
    load = open("/proc/loadavg").read().split()[0]
    results = []
    for sc in scenarios:
        name = os.path.basename(sc).replace(".scenario.yaml", "")
        with open(sc) as f:
            spec = yaml.safe_load(f)
        base_sens = float((spec.get("radio") or {}).get("sensitivity_dbm", -75.0))
        agents = int((spec.get("team") or {}).get("agents", 20))
        points = {}
        for s in sens:
            probe = os.path.join(a.results, name, "probe_%+g" % s)
            variant(sc, os.path.join(probe, "scenario.yaml"), base_sens + s)
            out, _ = sr.run([a.gather, "plan", os.path.join(probe, "scenario.yaml"), "--config", "bap:0", "--out", probe])
            m = re.search(r"coverage: ([\d.]+)% of the reachable space; farthest reachable cell ([\d.]+) m from it; "
                          r"request period ([\d.]+) s", out)
            if not m:
                die("no coverage line in the output of gather plan for %s" % probe)
            coverage, t0 = float(m.group(1)), float(m.group(3))
            for g in goals:
                for fct in periods:
                    tag = "s%+g_g%g_p%g" % (s, g, fct)
                    out_dir = os.path.join(a.results, name, tag)
                    scen = os.path.join(out_dir, "scenario.yaml")
                    variant(sc, scen, base_sens + s, goals=max(1, int(round(g * agents))), period=round(fct * t0, 3),
                            cycles=a.cycles)
                    rep = sr.report_scenario(a, scen, name="%s %s" % (name, tag), out=out_dir)
                    sim_dir = os.path.join(out_dir, "sim")
                    with_c = [c for c in rep["configs"] if c["active"] > 0]
                    without = [c for c in rep["configs"] if c["active"] == 0]
                    best_with = max(with_c, key=lambda c: c["r_u_interval"]) if with_c else None
                    best_without = max(without, key=lambda c: c["r_u_interval"]) if without else None
                    points[(s, g, fct)] = dict(
                        dir=out_dir, coverage=coverage, t0=t0, period=fct * t0, goals=max(1, int(round(g * agents))), report=rep,
                        best_with=best_with, best_without=best_without,
                        budget_with=role_budget(sim_dir, best_with["method"], best_with["nc"]) if best_with else {},
                        budget_without=role_budget(sim_dir, best_without["method"], best_without["nc"])
                        if best_without else {})
                    p = points[(s, g, fct)]
                    print("%-10s %-18s cov %5.1f%%  best E/R latency %-7s/%-7s interval %-7s/%-7s  sim %s s" % (
                        name, tag, coverage, point_label(rep["e_best_latency"]), point_label(rep["r_best_latency"]),
                        point_label(rep["e_best_interval"]), point_label(rep["r_best_interval"]),
                        "%.0f" % rep["sim_wall"] if rep["sim_wall"] is not None else "-"), flush=True)
        fig = os.path.join(a.results, name, "regimes_%s.png" % name)
        draw_map_figure(fig, "%s: best configuration per regime (%d seeds x %d cycles per point)" % (name, a.seeds, a.cycles),
                        points, sens, goals, periods)
        results.append((name, sc, points, fig))
    write_markdown(a, results, sens, goals, periods, load, time.monotonic() - t_start)
    print("wrote %s" % a.out)


def write_markdown(a, results, sens, goals, periods, load, wall):
    yn = lambda b: "yes" if b else "no"
    L = ["# Where collectors pay off: regimes\n"]
    how = "%.0f min on this 2-core machine, load average %s when it started" % (wall / 60.0, load)
    if a.reuse:  # keep what the run that produced the results took, if the report says
        old = open(a.out).read() if os.path.isfile(a.out) else ""
        m = re.search(r"tools/regime_report\.py`, (\d+ min on this 2-core machine, load average \S+ when it started)", old)
        how = (m.group(1) if m else "an earlier run") + "; report and figures redrawn from its results with --reuse"
    L.append("Produced by `make regime-report` (`tools/regime_report.py`, %s). On each map, for every radio sensitivity offset (the OC's coverage, "
             "given as its share of the reachable space), goals per request (per worker: G = that x team size) and "
             "request period (a factor of T0 = farthest reachable cell from the coverage / speed, the planner's "
             "default), `gather plan` sweeps the 27 configurations and `gather sim --all-configs` simulates each "
             "(%d seeds x %d cycles). A configuration uses collectors when some worker delivers to one "
             "(the association may leave all of them at the OC); *active* counts those. E = estimate, R = "
             "simulation; the utility is computed on both refresh metrics (docs/planner.md, \"Two refresh "
             "metrics\"). Nothing was tuned towards the seed's conclusions.\n" % (how, a.seeds, a.cycles))
    L.append("The seed's conclusions, checked at every point: (1) collectors beat no collectors, (2) the best "
             "number of collectors is 1-4, (3) BAP or PAP at least as good as RAP. Time budgets are "
             "measuring / commuting / waiting in % of the requests' span, from roles.csv, for the best "
             "configuration by R on the interval metric with collectors (its collector workers, its collectors) "
             "and without (its OC workers).\n")
    total = {}
    for name, sc, points, fig in results:
        L.append("\n## %s\n" % name)
        L.append("Scenario `%s`. Figure: `%s`.\n" % (os.path.relpath(sc, REPO), os.path.relpath(fig, REPO)))
        L.append("![%s](../%s)\n" % (name, os.path.relpath(fig, REPO)))
        L.append("| sens. [dB] (coverage) | G | period [s] | best E / R latency | best E / R interval | "
                 "collectors pay off E / R, latency | E / R, interval | N_c in 1-4 E / R, interval | "
                 "BAP/PAP ≥ RAP R, interval | OC workers w/o | collector workers with | collectors with |")
        L.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for s in sens:
            for g in goals:
                for fct in periods:
                    p = points[(s, g, fct)]
                    r = p["report"]
                    for key in ("e_concl_latency", "r_concl_latency", "e_concl_interval", "r_concl_interval"):
                        t = total.setdefault(key, [0, 0, 0, 0])
                        for i in range(3):
                            t[i] += bool(r[key][i])
                        t[3] += 1
                    L.append("| %+g (%.0f%%) | %d | %.0f (%gx) | %s / %s | %s / %s | %s / %s | %s / %s | %s / %s | %s | %s | %s | %s |" % (
                        s, p["coverage"], p["goals"], p["period"], fct, point_label(r["e_best_latency"]),
                        point_label(r["r_best_latency"]), point_label(r["e_best_interval"]),
                        point_label(r["r_best_interval"]), yn(r["e_concl_latency"][0]), yn(r["r_concl_latency"][0]),
                        yn(r["e_concl_interval"][0]), yn(r["r_concl_interval"][0]), yn(r["e_concl_interval"][1]),
                        yn(r["r_concl_interval"][1]), yn(r["r_concl_interval"][2]),
                        fmt_budget(p["budget_without"], "oc_worker"), fmt_budget(p["budget_with"], "collector_worker"),
                        fmt_budget(p["budget_with"], "collector")))
    L.append("\n## Where collectors pay off\n")
    L.append("Every point where the best configuration by E or by R uses collectors, with the margin in U over "
             "the best configuration without (same metric, same side), and the time budgets (measuring / "
             "commuting / waiting, %) of that configuration's roles.\n")
    L.append("| map | sens. [dB] (coverage) | G | period | metric | side | best | U | best without | U | "
             "collector workers | collectors | OC workers |")
    L.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    hits = 0
    for name, sc, points, fig in results:
        for s in sens:
            for g in goals:
                for fct in periods:
                    p = points[(s, g, fct)]
                    r = p["report"]
                    for metric in ("latency", "interval"):
                        for side, letter in (("e", "E"), ("r", "R")):
                            best = r["%s_best_%s" % (side, metric)]
                            if best["active"] == 0:
                                continue
                            key = "%s_u_%s" % (side, metric)
                            without = max((c for c in r["configs"] if c["active"] == 0), key=lambda c: c[key],
                                          default=None)
                            budget = role_budget(os.path.join(p["dir"], "sim"), best["method"], best["nc"])
                            hits += 1
                            L.append("| %s | %+g (%.0f%%) | %d | %.0f s | %s | %s | %s | %.3f | %s | %s | %s | %s | %s |" % (
                                name, s, p["coverage"], p["goals"], p["period"], metric, letter, point_label(best),
                                best[key], point_label(without) if without else "–",
                                "%.3f" % without[key] if without else "–", fmt_budget(budget, "collector_worker"),
                                fmt_budget(budget, "collector"), fmt_budget(budget, "oc_worker")))
    if hits == 0:
        L.append("| (none) | | | | | | | | | | | | |")
    L.append("\n## Totals\n")
    names = ("collectors beat no collectors", "the best N_c lies in 1-4", "BAP or PAP at least as good as RAP")
    for i, what in enumerate(names):
        L.append("- %s: latency E %d, R %d; interval E %d, R %d (of %d points)." % (
            what, total["e_concl_latency"][i], total["r_concl_latency"][i], total["e_concl_interval"][i],
            total["r_concl_interval"][i], total["e_concl_latency"][3]))
    with open(a.out, "w") as f:
        f.write("\n".join(L) + "\n")


if __name__ == "__main__":
    main()
