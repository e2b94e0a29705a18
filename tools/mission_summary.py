#!/usr/bin/env python3
"""Prints the summary table of a mission run from its results directory
(mission.yaml written by oc_node, fleet.yaml by fleet_node).

  tools/mission_summary.py results/mission

Exit status 0 if the run is complete (every agent heard, every agent process
stopped cleanly), 1 otherwise, 2 if the results are missing or unreadable.
"""
import os
import sys

import yaml


def load(path):
    try:
        with open(path) as f:
            return yaml.safe_load(f)
    except OSError as e:
        print("mission_summary: %s: %s" % (path, e.strerror), file=sys.stderr)
        sys.exit(2)
    except yaml.YAMLError as e:
        print("mission_summary: %s: not valid YAML (%s)" % (path, str(e).splitlines()[0]), file=sys.stderr)
        sys.exit(2)


def main():
    if len(sys.argv) != 2:
        print("usage: mission_summary.py RESULTS_DIR", file=sys.stderr)
        return 2
    d = sys.argv[1]
    mission = load(os.path.join(d, "mission.yaml"))
    fleet = load(os.path.join(d, "fleet.yaml"))
    stops = {a["id"]: a for a in fleet["agents"]}

    print("mission  %s" % mission["scenario"])
    print("map      %d x %d cells at %.3f m/cell, OC at [%.2f, %.2f] m" % (
        mission["map"]["width"], mission["map"]["height"], mission["map"]["resolution"],
        mission["oc"][0], mission["oc"][1]))
    print("run      %.1f s, %d/%d agents heard, %d heartbeats, %d missed, %d rejected" % (
        mission["duration_s"], mission["agents_heard"], mission["agents_expected"],
        mission["heartbeats"], mission["missed"], mission["rejected"]))
    print()
    print("%5s  %-10s  %10s  %8s  %6s  %-18s  %4s  %9s" % (
        "agent", "role", "heartbeats", "last_seq", "missed", "pose [m]", "exit", "stop [ms]"))
    for a in mission["agents"]:
        s = stops.get(a["id"], {})
        latency = s.get("stop_latency_s", -1)
        print("%5d  %-10s  %10d  %8d  %6d  %-18s  %4s  %9s" % (
            a["id"], a["role"], a["heartbeats"], a["last_seq"], a["missed"],
            "[%.2f, %.2f]" % tuple(a["pose"]) if a["heard"] else "never heard",
            s.get("exit_status", "?"), "%.1f" % (latency * 1e3) if latency >= 0 else "-"))
    print()
    bag = os.path.join(d, "mission.bag")
    ok = mission["status"] == "ok" and fleet["status"] == "ok"
    print("result   %s (mission %s, fleet %s)%s" % (
        "OK" if ok else "FAILED", mission["status"], fleet["status"],
        ", bag %s" % bag if os.path.exists(bag) else ""))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
