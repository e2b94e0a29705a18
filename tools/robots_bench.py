#!/usr/bin/env python3
"""The team on gather_world's MRPT robots beside ideal bases (make bench-robots).

For maps/office and ipa/office_a, a pap:4 plan and the scenario's best plan,
and the best plan of maps/warehouse, campus, cave and campus_busy (collectors), SEEDS seeds x CYCLES
cycles each (default 5 x 10): `gather run --robots mrpt`
and `gather run --protocol robots` (ideal bases, the same protocol), then
per configuration:

- delivered goals on robots and on ideal bases, and their ratio; and on
  ideal bases at 0.9 and 0.8 times the team speed (`--speed-factor`), the
  same plan: what a team that holds only that pace delivers (a lone MRPT
  robot holds about the team speed by default, 0.85-0.88 of it with a top
  speed equal to it: docs/robots.md);
- both refresh metrics (latency: delivered - requested; interval: per area,
  between two deliveries), robots / ideal;
- what the robots did: waypoints reached, the share reached late (more than
  0.5 s after their planned time) and by how much (median, max over the
  agents' medians and maxima), collectors' delay at the end of each loop,
  navigation failures, goals unreachable, robot-robot contacts;
- whether nothing was lost: every goal in one final state, none delivered twice;
- how fast the world runs: mission seconds per wall second of each robot run,
  the agents in one process with gather_world beside them (20 robots).

Writes docs/robots_bench.md (the table docs/robots.md and the README quote)
and prints it. Run from the repository root with the workspace built:
  tools/robots_bench.py [--seeds 5] [--cycles 10] [--out results/robots_bench]
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
GATHER = os.path.join(REPO, "catkin_ws", "devel", "lib", "gather_core", "gather")
# (name, scenario, configurations): office and ipa/office_a with pap:4 and
# their best plans, and every other shipped scenario's best plan.
SCENARIOS = [("office", os.path.join(REPO, "maps", "office.scenario.yaml"), ("pap:4", "best")),
             ("office_a", os.path.join(REPO, "..", "shared", "maps", "ipa", "office_a.scenario.yaml"), ("pap:4", "best")),
             ("warehouse", os.path.join(REPO, "maps", "warehouse.scenario.yaml"), ("best",)),
             ("campus", os.path.join(REPO, "maps", "campus.scenario.yaml"), ("best",)),
             ("cave", os.path.join(REPO, "maps", "cave.scenario.yaml"), ("best",)),
             ("campus_busy", os.path.join(REPO, "maps", "campus_busy.scenario.yaml"), ("best",))]
SLOW = (0.9, 0.8)  # ideal bases at these fractions of the team speed
FINAL = {"delivered", "expired", "dropped_overflow", "lost_with_agent", "unreachable"}


class RunFailed(Exception):
    pass


def run(args, fatal=True):
    t0 = time.time()
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        what = "%s failed (%d): %s" % (" ".join(args[:5]), p.returncode, p.stderr.strip()[-500:])
        if fatal:
            sys.exit("robots_bench: " + what)
        raise RunFailed(what)
    return p.stdout, time.time() - t0


def rows(path, name):
    with open(os.path.join(path, name)) as f:
        return list(csv.DictReader(f))


def summary(path):
    s = rows(path, "summary.csv")[0]
    return {k: float(s[k]) for k in ("delivered", "refresh_mean_s", "interval_mean_s", "expired", "lost_with_agent",
                                     "unreachable", "mission_s")}


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--seeds", type=int, default=5)
    p.add_argument("--cycles", type=int, default=10)
    p.add_argument("--out", default=os.path.join(REPO, "results", "robots_bench"))
    p.add_argument("--doc", default=os.path.join(REPO, "docs", "robots_bench.md"))
    p.add_argument("--only", default="", help="only these scenarios (comma-separated names: office,cave)")
    p.add_argument("--world-config", default="",
                   help="gather_world's YAML for the robots (e.g. robot.max_speed above the team speed); "
                        "write the table elsewhere (--doc)")
    p.add_argument("--reuse", action="store_true",
                   help="keep the runs already in --out (an interrupted bench goes on where it stopped)")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    lines, failures = [], []
    only = set(filter(None, a.only.split(",")))
    unknown = only - {name for name, _, _ in SCENARIOS}
    if unknown:
        sys.exit("robots_bench: --only: no scenario %s (%s)" % (", ".join(sorted(unknown)),
                                                               ", ".join(n for n, _, _ in SCENARIOS)))
    world = ["--world-config", os.path.abspath(a.world_config)] if a.world_config else []
    for name, scenario, configs in SCENARIOS:
        if only and name not in only:
            continue
        for config in configs:
            plan = os.path.join(a.out, "%s_%s" % (name, config.replace(":", "")))
            args = [GATHER, "plan", scenario, "--out", plan]
            if config != "best":
                args += ["--config", config]
            run(args)
            method = re.search(r"^method: (\w+)", open(os.path.join(plan, "plan.yaml")).read(), re.M).group(1)
            nc = int(re.search(r"^collectors: (\d+)", open(os.path.join(plan, "plan.yaml")).read(), re.M).group(1))
            label = "%s %s (%s:%d)" % (name, config, method, nc)
            ideal, robots, speed, agents, lost, twice, slow = [], [], [], [], 0, 0, {}
            for seed in range(1, a.seeds + 1):
                i_out = os.path.join(a.out, "%s_%s_ideal_%d" % (name, config.replace(":", ""), seed))
                r_out = os.path.join(a.out, "%s_%s_mrpt_%d" % (name, config.replace(":", ""), seed))
                timing = os.path.join(r_out, "bench_speed.txt")  # x real time, wall [s] of the robot run
                if not (a.reuse and os.path.exists(os.path.join(i_out, "summary.csv"))):
                    run([GATHER, "run", plan, "--out", i_out, "--cycles", str(a.cycles), "--seed", str(seed),
                         "--protocol", "robots"])
                for f in SLOW:
                    f_out = "%s_x%02d" % (i_out, round(100 * f))
                    if not (a.reuse and os.path.exists(os.path.join(f_out, "summary.csv"))):
                        run([GATHER, "run", plan, "--out", f_out, "--cycles", str(a.cycles), "--seed", str(seed),
                             "--protocol", "robots", "--speed-factor", str(f)])
                if not (a.reuse and os.path.exists(timing)):
                    try:
                        out, wall = run([GATHER, "run", plan, "--out", r_out, "--cycles", str(a.cycles), "--seed",
                                         str(seed), "--robots", "mrpt"] + world, fatal=False)
                    except RunFailed as e:  # reported under the table, the seed left out of its row
                        failures.append("%s seed %d: %s" % (label, seed, e))
                        print(failures[-1], flush=True)
                        continue
                    m = re.search(r"run (\d+) ms for (\d+) s of mission", out)
                    with open(timing, "w") as f:
                        f.write("%f %f\n" % (float(m.group(2)) / (float(m.group(1)) / 1000.0), wall))
                x, wall = (float(v) for v in open(timing).read().split())
                ideal.append(summary(i_out))
                for f in SLOW:
                    slow.setdefault(f, []).append(summary("%s_x%02d" % (i_out, round(100 * f))))
                robots.append(summary(r_out))
                speed.append(x)
                agents += rows(r_out, "agents.csv")
                g = rows(r_out, "goals.csv")
                lost += sum(r["state"] not in FINAL for r in g)
                twice += len(g) - len({r["goal"] for r in g})
                print("%s seed %d: delivered %d on robots, %d ideal; %.1fx real time (%.0f s)"
                      % (label, seed, robots[-1]["delivered"], ideal[-1]["delivered"], speed[-1], wall), flush=True)

            def mean(xs, k):
                return statistics.mean(x[k] for x in xs)

            legs = sum(int(r["legs"]) for r in agents)
            late = sum(int(r["legs_late"]) for r in agents)
            lat = [float(r["late_median_s"]) for r in agents if int(r["legs_late"]) > 0]
            lat_max = max([float(r["late_max_s"]) for r in agents] + [0.0])
            loops = [r for r in agents if r["role"] == "collector" and int(r["loops"]) > 0]
            loop_med = statistics.median([float(r["loop_late_median_s"]) for r in loops]) if loops else 0.0
            loop_max = max([float(r["loop_late_max_s"]) for r in loops] + [0.0])
            lines.append({
                "config": label + ("" if len(robots) == a.seeds else " [%d of %d seeds]" % (len(robots), a.seeds)),
                "ideal": mean(ideal, "delivered"), "robots": mean(robots, "delivered"),
                "slow": " / ".join("%.1f" % mean(slow[f], "delivered") for f in SLOW),
                "ratio": mean(robots, "delivered") / max(1e-9, mean(ideal, "delivered")),
                "lat": mean(robots, "refresh_mean_s") / max(1e-9, mean(ideal, "refresh_mean_s")),
                "int": mean(robots, "interval_mean_s") / max(1e-9, mean(ideal, "interval_mean_s")),
                "legs": legs, "late": 100.0 * late / max(1, legs),
                "late_med": statistics.median(lat) if lat else 0.0, "late_max": lat_max,
                "loops": sum(int(r["loops"]) for r in loops), "loop_med": loop_med, "loop_max": loop_max,
                "fail": sum(int(r["nav_failures"]) for r in agents),
                "unreach": mean(robots, "unreachable"), "lost": mean(robots, "lost_with_agent"),
                "contacts": sum(int(r["contacts"]) for r in agents) / max(1, len(robots)),
                "bad": lost + twice,
                "speed": statistics.median(speed), "speed_min": min(speed),
            })
    head = ("| configuration | delivered, ideal | delivered, robots | robots / ideal | ideal at %s x speed | "
            % " / ".join("%.1f" % f for f in SLOW) + "latency r/i | interval r/i | "
            "waypoints (late %) | late median / max [s] | collector loops: late median / max [s] | nav failures | "
            "unreachable | lost with an agent | contacts | not accounted | x real time (min) |")
    table = [head, "|" + "---|" * (head.count("|") - 1)]
    for l in lines:
        table.append("| %s | %.1f | %.1f | **%.2f** | %s | %.2f | %.2f | %d (%.0f%%) | %.1f / %.1f | %d: %.1f / %.1f | "
                     "%d | %.1f | %.1f | %.1f | %d | %.1f (%.1f) |"
                     % (l["config"], l["ideal"], l["robots"], l["ratio"], l["slow"], l["lat"], l["int"], l["legs"],
                        l["late"],
                        l["late_med"], l["late_max"], l["loops"], l["loop_med"], l["loop_max"], l["fail"],
                        l["unreach"], l["lost"], l["contacts"], l["bad"], l["speed"], l["speed_min"]))
    doc = ["# The team on MRPT robots beside ideal bases" +
           (" (robots: %s)" % os.path.basename(a.world_config) if a.world_config else ""),
           "",
           "Made by %s on %s, this machine: %d seeds "
           "x %d cycles a configuration; delivered goals are means per run, the metrics' ratios robots / ideal "
           "(ideal bases run the robots' protocol, `--protocol robots`; at 0.9 / 0.8 x speed: ideal bases at that "
           "fraction of the team speed, the same plan, `--speed-factor`); waypoints and failures summed over the "
           "runs, contacts per run. `not accounted`: goals not in exactly one final state, or delivered twice "
           "(must be 0). `x real time`: mission seconds per wall second of the robot runs (20 robots, the agents "
           "in one process, gather_world beside them), median and slowest." % (
               ("`make bench-robots` (`%s`)" if not (a.only or a.world_config) else "`%s`")
               % " ".join(["tools/robots_bench.py"] + sys.argv[1:]),
               time.strftime("%Y-%m-%d"), a.seeds, a.cycles),
           ""] + table + ([""] + ["Runs that failed (left out of their row):", ""] +
                          ["- " + f.replace("|", "/") for f in failures] if failures else [])
    with open(a.doc, "w") as f:
        f.write("\n".join(doc) + "\n")
    print("\n".join(table))
    return 0


if __name__ == "__main__":
    sys.exit(main())
