#!/usr/bin/env python3
"""The planner at scale (make bench-planner): `gather plan`'s whole sweep for
teams of 20, 50, 100 and 200 robots on maps/office and maps/campus (N_c from
0 to 40% of the team, every method), this build beside a reference build (a
static build of an older commit: tools/build-ref), run in turn.

Per map and team: the sweep's wall time (median of --runs runs of each
build; `gather plan` prints it), the whole process's peak memory, the
stages' CPU summed over the configurations (report.csv: partition, graph,
routes, estimate, association), and whether both builds chose the same plan
(plan.yaml byte for byte). Writes docs/planner_bench.md and its figure
docs/planner_bench.png (sweep wall time against team size, log-log).

  tools/planner_bench.py --ref build/planner_ref/build/gather_core/gather --new G
                         [--teams 20,50,100,200] [--ref-teams 20,50,100] [--maps office,campus] [--runs 3]

The reference runs only at the --ref-teams sizes (it takes 11-18 minutes a
sweep at 200 robots); at the others this build runs alone.
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
import time

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
MAPS = {"office": os.path.join(REPO, "maps", "office.scenario.yaml"),
        "campus": os.path.join(REPO, "maps", "campus.scenario.yaml")}
STAGES = ("partition_ms", "graph_ms", "routes_ms", "estimate_ms", "associate_ms")


def scenario_for(base, team, out):
    """The map's scenario with `team` robots and N_c 0..40% of it; the map by absolute path."""
    text = open(base).read()
    text = re.sub(r"^map: (\S+)", lambda m: "map: " + os.path.join(os.path.dirname(base), m.group(1)), text, 1,
                  re.M)
    text = re.sub(r"^  agents: \d+", "  agents: %d" % team, text, 1, re.M)
    text = re.sub(r"^  collectors: \[\d+, \d+\]", "  collectors: [0, %d]" % (team * 2 // 5), text, 1, re.M)
    path = os.path.join(out, "%s_%d.scenario.yaml" % (os.path.basename(base).split(".")[0], team))
    with open(path, "w") as f:
        f.write(text)
    return path


def same_plan(a, b):
    """How the plans in directories a and b compare: 'yes' when plan.yaml is
    byte-identical; 'yes, but U' when it differs only in the chosen plan's
    utility (normalised over the sweep's configurations, so it moves when
    another configuration's estimate does); 'estimates' digits' when only
    numbers with a decimal point differ (the estimates; the roles, the
    collectors' segments and the routes' stops are the same) and the
    partitions (labels.png) are too; else 'no'."""
    ta, tb = (open(os.path.join(d, "plan.yaml")).read() for d in (a, b))
    if ta == tb:
        return "yes"
    mask = lambda t: re.sub(r"utility: [0-9.eE+-]+", "utility: U", t)
    if mask(ta) == mask(tb):
        return "yes, but U"
    digits = lambda t: re.sub(r"-?\d+\.\d*(?:[eE][-+]?\d+)?", "X", t)
    if digits(ta) != digits(tb):
        return "no"
    from PIL import Image
    la, lb = (Image.open(os.path.join(d, "labels.png")) for d in (a, b))
    return "estimates' digits" if la.size == lb.size and la.tobytes() == lb.tobytes() else "no"


def plan_once(gather, scenario, out):
    """(sweep wall [s], peak memory [MiB], stage CPU sums [s], context [s]) of one
    `gather plan`: the sweep's wall time and, before it, the planning
    context's (what every configuration shares), as gather prints them."""
    os.makedirs(out, exist_ok=True)
    mem = os.path.join(out, "peak_kib.txt")
    p = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", mem, gather, "plan", scenario, "--out", out],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit("%s: %s plan %s failed (%d): %s" % (os.path.basename(sys.argv[0]), gather, scenario, p.returncode,
                                                    p.stderr[-500:]))
    peak = float(open(mem).read().split()[-1])
    m = re.search(r"sweep wall (\d+) ms", p.stdout + p.stderr)
    c = re.search(r"stages \[ms, summed over configurations\]: context (\d+)", p.stdout + p.stderr)
    if not m or not c:
        sys.exit("%s: %s printed no 'context' or no 'sweep wall' figure" % (os.path.basename(sys.argv[0]), gather))
    stages = dict.fromkeys(STAGES, 0.0)
    with open(os.path.join(out, "report.csv")) as f:
        for row in csv.DictReader(f):
            for s in STAGES:
                stages[s] += float(row[s]) / 1000.0
    return float(m.group(1)) / 1000.0, peak / 1024.0, stages, float(c.group(1)) / 1000.0


def figure(rows, path):
    """Sweep wall time against team size, log-log, one line per map and build."""
    from PIL import Image, ImageDraw, ImageFont
    import math
    W, H, L, R, T, B = 900, 560, 90, 230, 40, 70
    img = Image.new("RGB", (W, H), "white")
    d = ImageDraw.Draw(img)
    try:
        font = ImageFont.truetype("DejaVuSans.ttf", 15)
    except OSError:
        font = ImageFont.load_default()
    teams = sorted({r["team"] for r in rows})
    ys = [r[k] for r in rows for k in ("ref_wall", "new_wall") if r[k] > 0]
    x0, x1 = math.log10(min(teams) / 1.2), math.log10(max(teams) * 1.2)
    y0, y1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
    y1 = max(y1, y0 + 1)

    def px(team):
        return L + (math.log10(team) - x0) / (x1 - x0) * (W - L - R)

    def py(sec):
        return H - B - (math.log10(sec) - y0) / (y1 - y0) * (H - T - B)
    d.rectangle([L, T, W - R, H - B], outline="black")
    for e in range(y0, y1 + 1):
        for m in (1, 2, 5):
            v = m * 10 ** e
            if 10 ** y0 <= v <= 10 ** y1:
                y = py(v)
                d.line([L, y, W - R, y], fill=(225, 225, 225) if m > 1 else (190, 190, 190))
                d.text((L - 8, y), ("%g s" % v), fill="black", font=font, anchor="rm")
    for t in teams:
        x = px(t)
        d.line([x, T, x, H - B], fill=(225, 225, 225))
        d.text((x, H - B + 8), str(t), fill="black", font=font, anchor="mt")
    d.text(((L + W - R) / 2, H - 30), "robots in the team (N_c 0..40% of it, 3 methods)", fill="black", font=font,
           anchor="mm")
    d.text((L, 12), "gather plan: the whole sweep's wall time (2 threads)", fill="black", font=font)
    colours = {"office": (31, 119, 180), "campus": (214, 39, 40)}
    legend_y = T + 10
    def line(a, b, colour, dash):
        if not dash:
            d.line([a, b], fill=colour, width=3)
            return
        n = max(2, int(math.hypot(b[0] - a[0], b[1] - a[1]) / 8))
        for k in range(0, n, 2):
            d.line([a[0] + (b[0] - a[0]) * k / n, a[1] + (b[1] - a[1]) * k / n,
                    a[0] + (b[0] - a[0]) * (k + 1) / n, a[1] + (b[1] - a[1]) * (k + 1) / n], fill=colour, width=3)

    def dot(x, y, colour, hollow):
        d.ellipse([x - 4, y - 4, x + 4, y + 4], fill="white" if hollow else colour, outline=colour, width=2)

    for name in sorted({r["map"] for r in rows}):
        for build, dash in (("new", False), ("ref", True)):
            pts = sorted((px(r["team"]), py(r[build + "_wall"])) for r in rows
                         if r["map"] == name and r[build + "_wall"] > 0)
            if not pts:  # the reference not run on this map: no legend entry either
                continue
            for a, b in zip(pts, pts[1:]):
                line(a, b, colours[name], dash)
            for x, y in pts:
                dot(x, y, colours[name], dash)
            line((W - R + 15, legend_y), (W - R + 45, legend_y), colours[name], dash)
            dot(W - R + 30, legend_y, colours[name], dash)
            d.text((W - R + 52, legend_y), "%s, %s" % (name, "this build" if build == "new" else "reference"),
                   fill="black", font=font, anchor="lm")
            legend_y += 24
    img.save(path)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--ref", required=True, help="the reference build's gather (tools/build-ref)")
    p.add_argument("--ref-name", default="", help="what the reference is (its commit), for the table")
    p.add_argument("--new", required=True, help="this build's gather")
    p.add_argument("--teams", default="20,50,100,200")
    p.add_argument("--ref-teams", default="20,50,100",
                   help="the team sizes at which the reference runs too ('all' for every one)")
    p.add_argument("--maps", default="office,campus")
    p.add_argument("--runs", type=int, default=3, help="runs of each build per size (the median is shown)")
    p.add_argument("--out", default=os.path.join(REPO, "results", "planner_bench"))
    p.add_argument("--doc", default=os.path.join(REPO, "docs", "planner_bench.md"))
    a = p.parse_args()
    try:
        teams = [int(t) for t in a.teams.split(",")]
        ref_teams = set(teams) if a.ref_teams == "all" else {int(t) for t in a.ref_teams.split(",") if t}
    except ValueError:
        sys.exit("planner_bench: --teams and --ref-teams must be numbers, e.g. 20,50,100 (--ref-teams: or all)")
    if any(t < 2 or t > 1000 for t in teams) or not 1 <= a.runs <= 20:
        sys.exit("planner_bench: teams in 2..1000, --runs in 1..20")
    if ref_teams - set(teams):
        print("planner_bench: --ref-teams %s not in --teams: ignored" % ",".join(map(str, sorted(ref_teams - set(teams)))),
              file=sys.stderr)
    maps = a.maps.split(",")
    for m in maps:
        if m not in MAPS:
            sys.exit("planner_bench: --maps: no map %s (%s)" % (m, ", ".join(MAPS)))
    for g in (a.ref, a.new):
        if not os.access(g, os.X_OK):
            sys.exit("planner_bench: %s is not an executable (make bench-planner builds both)" % g)
    os.makedirs(a.out, exist_ok=True)
    load = open("/proc/loadavg").read().split()[0]
    rows = []
    for name in maps:
        for team in teams:
            scenario = scenario_for(MAPS[name], team, a.out)
            builds = (("ref", a.ref), ("new", a.new)) if team in ref_teams else (("new", a.new),)
            got = {"ref": [], "new": []}
            for k in range(a.runs):
                for build, g in builds:  # in turn
                    got[build].append(plan_once(g, scenario, os.path.join(a.out, "%s_%d_%s" % (name, team, build))))
            row = {"map": name, "team": team, "same": "-", "ref_ran": bool(got["ref"])}
            if got["ref"]:
                row["same"] = same_plan(os.path.join(a.out, "%s_%d_ref" % (name, team)),
                                        os.path.join(a.out, "%s_%d_new" % (name, team)))
            for build in ("ref", "new"):
                row[build + "_wall"] = statistics.median(r[0] for r in got[build]) if got[build] else 0.0
                row[build + "_context"] = statistics.median(r[3] for r in got[build]) if got[build] else 0.0
                row[build + "_mib"] = max(r[1] for r in got[build]) if got[build] else 0.0
                row[build + "_stages"] = {s: statistics.median(r[2][s] for r in got[build]) if got[build] else None
                                          for s in STAGES}
            rows.append(row)
            print("%s %d robots: sweep wall %.2f s (reference %s), peak %.0f MiB (%s), same plan: %s"
                  % (name, team, row["new_wall"], "%.2f s" % row["ref_wall"] if got["ref"] else "not run",
                     row["new_mib"], "%.0f" % row["ref_mib"] if got["ref"] else "-", row["same"]), flush=True)
    table = ["| map | robots | configurations | sweep wall, this build [s] | reference [s] | speed-up | "
             "context [s] (ref) | peak MiB (ref) | partition | graph | routes | estimate | association | same plan |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        st, rs, ran = r["new_stages"], r["ref_stages"], r["ref_ran"]
        table.append("| %s | %d | %d | **%.2f** | %s | %s | %.2f (%s) | %.0f (%s) | %s | %s | %s | %s | %s | %s |" % (
            r["map"], r["team"], 3 * (r["team"] * 2 // 5 + 1), r["new_wall"],
            "%.2f" % r["ref_wall"] if ran else "not run", "%.1fx" % (r["ref_wall"] / max(1e-9, r["new_wall"]))
            if ran else "-", r["new_context"], "%.2f" % r["ref_context"] if ran else "-", r["new_mib"],
            "%.0f" % r["ref_mib"] if ran else "-",
            *("%.1f (%s)" % (st[s], "%.1f" % rs[s] if ran else "-") for s in STAGES),
            r["same"] if r["same"] != "no" else "**no**"))
    png = os.path.splitext(a.doc)[0] + ".png"
    figure(rows, png)
    doc = ["# The planner at scale", "",
           "Made by `%s` on %s, this machine (2 cores): `gather plan`'s whole sweep (every method, N_c from 0 "
           "to 40%% of the team, 2 threads) on maps/office and maps/campus with the team sizes below, this build "
           "beside the reference build%s, run in turn, %d run(s) each (median)%s. Stages: CPU [s] summed over the "
           "configurations (report.csv), this build (reference). Context: the planning context every "
           "configuration shares (the coverage, the marches from the OC, the pair grid), made before the sweep "
           "and not in its wall time (median, wall). `same plan`: both builds wrote the same plan.yaml (`yes, but "
           "U`: all but the chosen plan's utility, which is normalised over the sweep's configurations and so "
           "moves when another configuration's estimate does; `estimates' digits`: only the estimates' numbers "
           "differ, the roles, routes' stops and partitions are the same). The load average was %s when it "
           "started." % (" ".join(["tools/planner_bench.py"] + [x for x in sys.argv[1:]]),
                         time.strftime("%Y-%m-%d"), " (" + a.ref_name + ")" if a.ref_name else "", a.runs,
                         "" if all(r["ref_ran"] for r in rows) else
                         "; the reference not run at %s robots (`--ref-teams`; it takes 11-18 minutes a sweep at "
                         "200)" % ", ".join(sorted({str(r["team"]) for r in rows if not r["ref_ran"]}, key=int)),
                         load),
           "", "![sweep wall time against team size](%s)" % os.path.basename(png), ""] + table
    with open(a.doc, "w") as f:
        f.write("\n".join(doc) + "\n")
    print("\n".join(table))
    print("-> %s, %s" % (a.doc, png))
    return 0


if __name__ == "__main__":
    sys.exit(main())
