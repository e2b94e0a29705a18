#!/usr/bin/env python3
"""End-to-end test of `roslaunch gather_oc mission.launch`.

Runs a real mission (the OC node plans the scenario and drives the lockstep
clock, the fleet of gather_agent processes executes it over LCM, rosbag
records) for a few cycles, and checks the results (mission.yaml, the CSVs:
every goal resolved, nothing lost), the fleet report (every agent ended by
itself with status 0), that the mission's goals.csv is byte for byte the one
of `gather run` in one process on the same plan and seed, the recorded /map
against the map file, and the markers of all N agents. A bad scenario or plan
must make the OC exit with status 2 and one line naming the file.

Must run inside a private network namespace with the workspace sourced:
  tools/netns-run bash -c 'source catkin_ws/devel/setup.bash && python3 tests/e2e/mission_e2e.py'
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
import yaml
from PIL import Image

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
results = []


def check(name, ok, detail=""):
    results.append(ok)
    print("%s %s%s" % ("ok  " if ok else "FAIL", name, "" if ok else ": " + detail), flush=True)
    return ok


def roslaunch(args, timeout):
    p = subprocess.run(["roslaunch", "gather_oc", "mission.launch"] + args, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, timeout=timeout, text=True)
    return p.returncode, p.stdout


def expected_map(scenario_path):
    """The map as map_server publishes it (trinary/scale of a gray image):
    nav_msgs values with row 0 at the bottom."""
    sc = yaml.safe_load(open(scenario_path))
    map_yaml = os.path.join(os.path.dirname(scenario_path), sc["map"])
    meta = yaml.safe_load(open(map_yaml))
    img = np.asarray(Image.open(os.path.join(os.path.dirname(map_yaml), meta["image"])).convert("L"), dtype=float)
    if meta.get("negate", 0):
        img = 255 - img
    occ = (255 - img) / 255.0
    vals = np.full(img.shape, -1, dtype=np.int8)
    vals[occ > meta["occupied_thresh"]] = 100
    vals[occ < meta["free_thresh"]] = 0
    return sc, meta, np.flipud(vals)


def check_bag(bag_path, scenario_path, n):
    import rosbag
    sc, meta, want = expected_map(scenario_path)
    maps, last_markers = [], None
    with rosbag.Bag(bag_path) as bag:
        for topic, msg, _ in bag.read_messages(topics=["/map", "/gather/markers"]):
            if topic == "/map":
                maps.append(msg)
            else:
                last_markers = msg
    if not check("bag has exactly one /map message (latched)", len(maps) == 1, "got %d" % len(maps)):
        return
    m = maps[0]
    h, w = want.shape
    check("/map size matches the image", (m.info.width, m.info.height) == (w, h),
          "%dx%d vs %dx%d" % (m.info.width, m.info.height, w, h))
    check("/map resolution and origin match the map YAML",
          abs(m.info.resolution - meta["resolution"]) < 1e-6 and
          abs(m.info.origin.position.x - meta["origin"][0]) < 1e-9 and
          abs(m.info.origin.position.y - meta["origin"][1]) < 1e-9 and m.header.frame_id == "map")
    got = np.frombuffer(bytes(bytearray((v & 0xff for v in m.data))), dtype=np.int8).reshape(h, w) \
        if not isinstance(m.data, (bytes, bytearray)) else np.frombuffer(m.data, dtype=np.int8).reshape(h, w)
    diff = int((got != want).sum())
    check("/map cells equal map_server's thresholding of the image", diff == 0, "%d cells differ" % diff)
    ox, oy = sc["oc"]
    col, row = int((ox - meta["origin"][0]) / meta["resolution"]), int((oy - meta["origin"][1]) / meta["resolution"])
    check("/map is free at the OC", got[row, col] == 0)
    ids = set()
    if last_markers is not None:
        ids = {mk.id for mk in last_markers.markers if mk.ns == "agents"}
    check("markers show all %d agents" % n, ids == set(range(n)), "missing %s" % sorted(set(range(n)) - ids))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scenario", default=os.path.join(REPO, "maps", "office.scenario.yaml"))
    ap.add_argument("--cycles", type=int, default=2)
    a = ap.parse_args()
    if os.environ.get("GATHER_NETNS") != "1":
        print("mission_e2e: run me inside tools/netns-run (LCM multicast must stay in a private namespace)",
              file=sys.stderr)
        return 2
    scenario = os.path.abspath(a.scenario)
    n = yaml.safe_load(open(scenario))["team"]["agents"]
    tmp = tempfile.mkdtemp(prefix="gather_e2e_")

    out_dir = os.path.join(tmp, "ok")
    rc, out = roslaunch(["scenario:=" + scenario, "cycles:=%d" % a.cycles, "results_dir:=" + out_dir,
                         "record:=true"], timeout=300)
    check("roslaunch exits 0", rc == 0, "status %d" % rc)
    check("OC prints its summary line", re.search(r"oc: mission done: \w+ Nc=\d+, %d cycles" % a.cycles, out)
          is not None, out[-2000:])
    mission_file = os.path.join(out_dir, "mission.yaml")
    plan_dir = os.path.join(out_dir, "plan")
    if check("results file written", os.path.exists(mission_file)):
        r = yaml.safe_load(open(mission_file))
        check("results: status ok", r["status"] == "ok", str(r.get("failure")))
        g = r["goals"]
        per_request = yaml.safe_load(open(scenario)).get("mission", {}).get("goals_per_request", 40)
        check("results: every goal requested resolved", g["requested"] == a.cycles * per_request and
              g["delivered"] + g["expired"] + g["dropped"] == g["requested"], str(g))
        check("results: some goals delivered, none dropped", g["delivered"] > 0 and g["dropped"] == 0, str(g))
        check("results: %d agents, each with its counters" % n, len(r["agents"]) == n and
              all(x["sent"] > 0 for x in r["agents"]), str(r["agents"][:2]))
        check("results: nothing still carried at the end", all(x["carried"] == 0 for x in r["agents"]))
        measured = sum(x["measured"] for x in r["agents"])
        check("results: every measured goal delivered", measured == g["delivered"],
              "%d measured, %d delivered" % (measured, g["delivered"]))
        check("results: no bad message", r["oc"]["bad"] == 0 and all(x["bad"] == 0 for x in r["agents"]))
        check("results: the plan it ran", r["plan"] == os.path.realpath(plan_dir), r["plan"])
    fleet_file = os.path.join(out_dir, "fleet.yaml")
    if check("fleet file written", os.path.exists(fleet_file)):
        f = yaml.safe_load(open(fleet_file))
        check("fleet: status ok", f["status"] == "ok", f["status"])
        bad = [x for x in f["agents"] if x["exit_status"] != 0]
        check("fleet: %d agents exited 0" % n, len(f["agents"]) == n and not bad, str(bad))
    for name in ("goals.csv", "cycles.csv", "summary.csv", "agents.csv"):
        check("%s written" % name, os.path.exists(os.path.join(out_dir, name)))
    # The same plan and seed in one process: the same goals, byte for byte.
    same_dir = os.path.join(tmp, "in_process")
    gather = os.path.join(REPO, "catkin_ws", "devel", "lib", "gather_core", "gather")
    p = subprocess.run([gather, "run", plan_dir, "--cycles", str(a.cycles), "--out", same_dir],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
    if check("gather run in one process on the mission's plan", p.returncode == 0, p.stdout[-1000:]):
        for name in ("goals.csv", "cycles.csv"):
            same = open(os.path.join(out_dir, name), "rb").read() == open(os.path.join(same_dir, name), "rb").read()
            check("%s of the mission == gather run in one process (byte for byte)" % name, same)
    bag = os.path.join(out_dir, "mission.bag")
    if check("bag recorded", os.path.exists(bag)):
        check_bag(bag, scenario, n)

    # Bad input through roslaunch: the OC exits 2 with one line; roslaunch still returns 0.
    bad_dir = os.path.join(tmp, "bad")
    missing = os.path.join(tmp, "no_such.scenario.yaml")
    rc, out = roslaunch(["scenario:=" + missing, "results_dir:=" + bad_dir], timeout=60)
    check("bad scenario: OC reports the file on one line", ("oc_node: %s: cannot open file" % missing) in out,
          out[-1500:])
    check("bad scenario: OC exits with status 2", re.search(r"process has died \[pid \d+, exit code 2, cmd \S*oc_node", out)
          is not None, out[-1500:])
    check("bad scenario: no results file", not os.path.exists(os.path.join(bad_dir, "mission.yaml")))
    rc, out = roslaunch(["scenario:=" + scenario, "plan:=" + os.path.join(tmp, "no_plan"), "results_dir:=" + bad_dir],
                        timeout=60)
    check("bad plan: OC names the directory and exits 2", ("oc_node: %s: no such plan directory" % os.path.join(tmp, "no_plan")) in out
          and re.search(r"exit code 2, cmd \S*oc_node", out) is not None, out[-1500:])

    failed = results.count(False)
    print("%d passed, %d failed" % (len(results) - failed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
