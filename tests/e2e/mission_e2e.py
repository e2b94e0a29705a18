#!/usr/bin/env python3
"""End-to-end test of `roslaunch gather_oc mission.launch`.

Runs a real mission (OC node, fleet of gather_agent processes over LCM, rosbag)
and checks the results file, the fleet report, the recorded /map message
against the map file, and the markers of all N agents. A bad scenario must make
the OC exit with status 2 and one line naming the file.

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
    ap.add_argument("--duration", type=float, default=8.0)
    ap.add_argument("--rate", type=float, default=5.0)
    a = ap.parse_args()
    if os.environ.get("GATHER_NETNS") != "1":
        print("mission_e2e: run me inside tools/netns-run (LCM multicast must stay in a private namespace)",
              file=sys.stderr)
        return 2
    scenario = os.path.abspath(a.scenario)
    n = yaml.safe_load(open(scenario))["team"]["agents"]
    tmp = tempfile.mkdtemp(prefix="gather_e2e_")

    out_dir = os.path.join(tmp, "ok")
    rc, out = roslaunch(["scenario:=" + scenario, "duration:=%g" % a.duration, "results_dir:=" + out_dir,
                         "record:=true", "heartbeat_rate:=%g" % a.rate], timeout=a.duration + 90)
    check("roslaunch exits 0", rc == 0, "status %d" % rc)
    check("OC prints its summary line", re.search(r"oc: mission done after [\d.]+ s: %d/%d agents heard" % (n, n), out)
          is not None, out[-2000:])
    mission_file = os.path.join(out_dir, "mission.yaml")
    if check("results file written", os.path.exists(mission_file)):
        r = yaml.safe_load(open(mission_file))
        check("results: status ok", r["status"] == "ok", r["status"])
        check("results: all %d agents heard" % n, r["agents_heard"] == n == r["agents_expected"])
        # Rate measured between the first and the last heartbeat the OC heard:
        # start-up of 20 processes on a loaded machine must not count.
        off = []
        for x in r["agents"]:
            span = x["last_heard_s"] - x["first_heard_s"]
            if x["heartbeats"] < 3 or span <= 0:
                off.append((x["id"], x["heartbeats"]))
                continue
            rate = (x["heartbeats"] - 1) / span
            if span >= 2.0 and abs(rate - a.rate) > 0.25 * a.rate:
                off.append((x["id"], round(rate, 2)))
        check("results: every agent heard >= 3 times, at its heartbeat rate", not off, "agents (id, rate) %s" % off)
        gaps = [x["id"] for x in r["agents"] if x["missed"] or x["out_of_order"] or x["first_seq"] != 0]
        check("results: sequence numbers complete and in order", not gaps, "agents %s" % gaps)
        check("results: nothing rejected", r["rejected"] == 0, str(r["rejected"]))
        ox, oy = r["oc"]
        far = [x["id"] for x in r["agents"] if np.hypot(x["pose"][0] - ox, x["pose"][1] - oy) > 8.0]
        check("results: agents start near the OC", not far, "agents %s" % far)
    fleet_file = os.path.join(out_dir, "fleet.yaml")
    if check("fleet file written", os.path.exists(fleet_file)):
        f = yaml.safe_load(open(fleet_file))
        check("fleet: status ok", f["status"] == "ok", f["status"])
        bad = [x for x in f["agents"] if x["exit_status"] != 0 or x["exited_early"] or not 0 <= x["stop_latency_s"] < 1.0]
        check("fleet: %d agents exited 0 within 1 s of SIGTERM" % n, len(f["agents"]) == n and not bad, str(bad))
    bag = os.path.join(out_dir, "mission.bag")
    if check("bag recorded", os.path.exists(bag)):
        check_bag(bag, scenario, n)

    # Bad input through roslaunch: the OC exits 2 with one line; roslaunch still returns 0.
    bad_dir = os.path.join(tmp, "bad")
    missing = os.path.join(tmp, "no_such.scenario.yaml")
    rc, out = roslaunch(["scenario:=" + missing, "duration:=3", "results_dir:=" + bad_dir], timeout=60)
    check("bad scenario: OC reports the file on one line", ("oc_node: %s: cannot open file" % missing) in out,
          out[-1500:])
    check("bad scenario: OC exits with status 2", re.search(r"process has died \[pid \d+, exit code 2, cmd \S*oc_node", out)
          is not None, out[-1500:])
    check("bad scenario: no results file", not os.path.exists(os.path.join(bad_dir, "mission.yaml")))

    failed = results.count(False)
    print("%d passed, %d failed" % (len(results) - failed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
