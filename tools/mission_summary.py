#!/usr/bin/env python3
"""Prints what a mission did, from its results directory (mission.yaml
written by oc_node, fleet.yaml by fleet_node).

  tools/mission_summary.py results/mission

Exit status 0 if the mission is complete (every goal resolved, every agent
process exited 0), 1 otherwise, 2 if the results are missing or unreadable.
"""
import csv
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


def through_collectors(path):
    """(delivered goals, those a collector picked up, the collectors that did) from goals.csv."""
    try:
        with open(path, newline="") as f:
            rows = [r for r in csv.DictReader(f) if r.get("state") == "delivered"]
    except OSError as e:
        print("mission_summary: %s: %s" % (path, e.strerror), file=sys.stderr)
        sys.exit(2)
    try:
        by = [int(r["picked_up_by"]) for r in rows]
    except (KeyError, TypeError, ValueError):
        print("mission_summary: %s: no readable picked_up_by column" % path, file=sys.stderr)
        sys.exit(2)
    carried = [b for b in by if b >= 0]
    return len(rows), len(carried), len(set(carried))


def main():
    if len(sys.argv) != 2:
        print("usage: mission_summary.py RESULTS_DIR", file=sys.stderr)
        return 2
    d = sys.argv[1]
    m = load(os.path.join(d, "mission.yaml"))
    fleet = load(os.path.join(d, "fleet.yaml"))
    try:
        exits = {a["id"]: a for a in fleet["agents"]}
        cfg, run, goals, refresh = m["configuration"], m["run"], m["goals"], m["refresh"]
    except (KeyError, TypeError) as e:
        print("mission_summary: %s: missing field %s" % (d, e), file=sys.stderr)
        return 2

    print("mission  %s" % m["scenario"])
    print("plan     %s: %s, %d collectors, %d workers" % (m["plan"], cfg["method"], cfg["collectors"], cfg["workers"]))
    print("run      %d cycles of %.1f s over %s, tick %.2f s: %d ticks, %.1f s of mission in %.1f s = %.0fx real time, "
          "%d messages" % (run["cycles"], run["period_s"], run["transport"], run["tick_s"], run["ticks"], run["end_s"],
                           run["wall_s"], run["speedup"], run["messages"]))
    if m["status"] != "ok":
        print("FAILED   %s" % m.get("failure", "mission incomplete"))
    else:
        print("goals    %d requested, %d delivered (%.2f per cycle, est. %.2f), %d expired, %d dropped" % (
            goals["requested"], goals["delivered"], goals["per_cycle"], goals["est_per_cycle"], goals["expired"],
            goals["dropped"]))
        print("refresh  mean %.1f s (est. %.1f s), max %.1f s" % (refresh["mean_s"], refresh["est_s"], refresh["max_s"]))
        delivered, carried, collectors = through_collectors(os.path.join(d, "goals.csv"))
        if cfg["collectors"] == 0:
            print("carried  no collector in the plan: every worker brought its data to the OC itself")
        else:
            print("carried  %d of %d delivered goals came through a collector (%.0f%%), picked up on the move by %d of "
                  "the plan's %d collectors" % (carried, delivered, 100.0 * carried / max(delivered, 1), collectors,
                                                cfg["collectors"]))
    print()
    cols = ("agent", "role", "measured", "carried", "delivered", "expired", "skipped", "dropped", "sent", "received",
            "gated", "lost", "exit")
    fmt = "%5s  %-9s  %8s  %7s  %9s  %7s  %7s  %7s  %6s  %8s  %7s  %5s  %4s"
    print(fmt % cols)
    for a in m["agents"]:
        e = exits.get(a["id"], {})
        print(fmt % (a["id"], a["role"], a["measured"], a["carried"], a["delivered"], a["expired"], a["skipped"],
                     a["dropped"], a["sent"], a["received"], a["gated"], a["lost"], e.get("exit_status", "?")))
    oc = m["oc"]
    print(fmt % ("OC", "oc", "", "", sum(a["delivered"] for a in m["agents"]), "", "", "", oc["sent"], oc["received"],
                 oc["gated"], oc["lost"], "-"))
    print("         goals: measured, carried (held at the end), delivered (brought into the OC's coverage),\n"
          "         expired (reported not measured in time), dropped (no room to store); skipped: requests that\n"
          "         never reached the agent in time (their goals there expire); radio messages: sent, received,\n"
          "         gated (out of range), lost (injected loss); exit: the agent process's exit status")
    print()
    bag = os.path.join(d, "mission.bag")
    ok = m["status"] == "ok" and fleet["status"] == "ok"
    print("result   %s (mission %s, fleet %s)%s" % ("OK" if ok else "FAILED", m["status"], fleet["status"],
                                                    ", bag %s" % bag if os.path.exists(bag) else ""))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
