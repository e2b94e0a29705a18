#!/usr/bin/env python3
"""End-to-end test of the mission in ROS (`roslaunch gather_oc mission.launch`
and `review.launch`), with RViz on a virtual display.

0. The default mission of `make run` (the Makefile's SCENARIO, one cycle,
   no RViz): the OC plans it, the best plan has collectors that workers
   hand their data to, and tools/mission_summary.py counts the goals that
   came through a collector (some did).
1. maps/office with a collector plan (gather plan --config pap:4 --association
   off: every far segment served by one of the 4 collectors), RViz and
   rosbag: a quiet end (exit 0, no "REQUIRED process has died"), the results
   (every goal resolved, the fleet exited 0 by itself), goals.csv byte for
   byte the one of `gather run` in one process, the bag (its topics, /clock,
   TF map -> agent_k/base_link for every agent, agents moving away from the
   OC, the recorded /map against the map file, every agent's marker), and two
   screenshots of RViz (the routes' colours and goals on screen, the picture
   changing far from the OC as the team moves out).
2. ../shared/maps/ipa/office_a with its own pap:4 plan: RViz's view fits this
   map too (a screenshot with its routes), then the launch is stopped with
   Ctrl-C (SIGINT) as a user would.
3. review.launch on the bag of 1: RViz shows the replay (a screenshot), and
   stays open after the bag ends.
4. map_topic:=/map with a node that publishes the map as map_server does and
   a scenario without `map:`: the mission runs on the received map (saved
   for the agents), with the same goals as `gather run` on the file's map.
5. The tools a ROS user reaches for: rostopic echo -p on the mission topics
   (from the bag), rosbag info, rosrun. 5c: faults: kill:= and restart:= on
   the launch under loss, the same goals as gather run.
6. Bad input through roslaunch: the OC exits 2 with one line naming the file.

The screenshots stay in results/e2e/ for a person to open. Must run inside a
private network namespace, on an X display, with the workspace sourced:
  tools/netns-run xvfb-run -a -s "-screen 0 1400x900x24" bash -c \\
    'source catkin_ws/devel/setup.bash && python3 tests/e2e/mission_e2e.py'
"""
import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import numpy as np
import yaml
from PIL import Image

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
GATHER = os.path.join(REPO, "catkin_ws", "devel", "lib", "gather_core", "gather")
SHOTS = os.path.join(REPO, "results", "e2e")
# The collectors' colours (gather_core/src/figures/palette.cpp) and the goals' (gather_oc/view_style.hpp).
COLLECTOR_RGB = [(30, 100, 200), (240, 130, 20), (40, 150, 40), (150, 50, 150)]
GOAL_RGB = {"pending": (255, 153, 0), "carried": (51, 115, 255), "delivered": (26, 179, 51), "expired": (217, 26, 26)}
results = []


def check(name, ok, detail=""):
    results.append(bool(ok))
    print("%s %s%s" % ("ok  " if ok else "FAIL", name, "" if ok else ": " + str(detail)), flush=True)
    return ok


def roslaunch(args, timeout, launch="mission.launch"):
    p = subprocess.run(["roslaunch", "gather_oc", launch] + args, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, timeout=timeout, text=True)
    return p.returncode, p.stdout


class Launch:
    """roslaunch in the background, its output in a file, screenshots on cue."""

    def __init__(self, args, log, launch="mission.launch", cwd=None):
        self.log = log
        self.f = open(log, "w")
        env = dict(os.environ)
        if cwd:
            env["PWD"] = cwd  # as a shell that cd'ed there would have it
        self.p = subprocess.Popen(["roslaunch"] + (["gather_oc", launch] if not launch.startswith("/") else [launch]) +
                                  args, stdout=self.f, stderr=subprocess.STDOUT, cwd=cwd, env=env)

    def output(self):
        self.f.flush()
        return open(self.log).read()

    def wait_for(self, pattern, timeout):
        t0 = time.time()
        while time.time() - t0 < timeout:
            if re.search(pattern, self.output()):
                return True
            if self.p.poll() is not None:
                return bool(re.search(pattern, self.output()))
            time.sleep(0.2)
        return False

    def wait(self, timeout):
        try:
            return self.p.wait(timeout)
        except subprocess.TimeoutExpired:
            return None

    def interrupt(self, timeout=30):
        if self.p.poll() is None:
            self.p.send_signal(signal.SIGINT)
        return self.wait(timeout)

    def close(self):
        if self.p.poll() is None:
            self.p.kill()
            self.p.wait()
        self.f.close()


def screenshot(path):
    subprocess.run(["import", "-window", "root", path], check=True, timeout=30)
    return np.asarray(Image.open(path).convert("RGB")).astype(int)


def wait_visible(path, label, timeout=90):
    """Screenshots until RViz has drawn something (its first start compiles shaders)."""
    t0 = time.time()
    while time.time() - t0 < timeout:
        img = screenshot(path)
        if int(near(img, (48, 48, 56), 4).sum()) > 20000:  # the 3D view's background, not the splash screen
            print("     %s: RViz on screen after %.1f s" % (label, time.time() - t0), flush=True)
            return True
        time.sleep(0.5)
    return False


def screen_counts(img, collectors):
    """Pixels of each collector's colour, and of each kind of goal marker."""
    routes = [int(near(img, COLLECTOR_RGB[c]).sum()) for c in range(collectors)]
    goals = {k: int(near(img, v, 22).sum()) for k, v in GOAL_RGB.items()}
    return routes, goals


def route_drawn(pixels):
    return pixels >= 150


def goals_drawn(goals):
    return sum(1 for v in goals.values() if v >= 20) >= 2


def drawn(img, collectors):
    """Every collector's colour and two kinds of goal markers on screen (check_screen's tests)."""
    routes, goals = screen_counts(img, collectors)
    return all(route_drawn(n) for n in routes) and goals_drawn(goals)


def screenshot_when_drawn(path, label, collectors, timeout=20):
    """Screenshots until RViz has drawn the plan and the goals (under load it
    shows the map a few seconds before the markers), at most `timeout` s;
    the last one is returned either way, for check_screen to judge."""
    t0 = time.time()
    while True:
        img = screenshot(path)
        if drawn(img, collectors) or time.time() - t0 >= timeout:
            print("     %s: markers on screen after %.1f s" % (label, time.time() - t0), flush=True)
            return img
        time.sleep(0.5)


def near(img, rgb, tol=28):
    return (np.abs(img - np.array(rgb)).max(axis=2) <= tol)


def check_screen(label, img, collectors):
    routes, goals = screen_counts(img, collectors)
    for c, n in enumerate(routes):
        check("%s: collector C%d's colour on screen (route, its workers)" % (label, c), route_drawn(n), "%d pixels" % n)
    check("%s: goal markers on screen" % label, goals_drawn(goals), str(goals))


def oc_pixel(img):
    """Centre of the OC's red cube: the largest dense block of its red."""
    m = near(img, (217, 20, 20), 30)
    ys, xs = np.nonzero(m)
    if xs.size == 0:
        return None
    # The cube is a filled square; the coverage outline a thin line: take the
    # red pixel with the most red around it.
    best, at = -1, None
    for y, x in zip(ys[::7], xs[::7]):
        s = int(m[max(0, y - 6):y + 7, max(0, x - 6):x + 7].sum())
        if s > best:
            best, at = s, (x, y)
    return at


def expected_map(scenario_path):
    """The map as map_server publishes it (trinary of a gray image), row 0 at the bottom."""
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


def check_bag(bag_path, scenario_path, n, collectors):
    import rosbag
    sc, meta, want = expected_map(scenario_path)
    with rosbag.Bag(bag_path) as bag:
        topics = bag.get_type_and_topic_info().topics
        for t in ["/map", "/clock", "/tf", "/gather/plan_markers", "/gather/team_markers", "/gather/goal_markers",
                  "/gather/path_markers", "/gather/agents", "/gather/status", "/gather/cycle", "/gather/agent_0/pose"]:
            check("bag has %s" % t, t in topics, sorted(topics))
        maps, last_team, frames, clocks, plan = [], None, {}, [], None
        for topic, msg, _ in bag.read_messages(topics=["/map", "/gather/team_markers", "/tf", "/clock",
                                                       "/gather/plan_markers"]):
            if topic == "/map":
                maps.append(msg)
            elif topic == "/gather/team_markers":
                last_team = msg
            elif topic == "/gather/plan_markers":
                plan = msg
            elif topic == "/clock":
                clocks.append(msg.clock.to_sec())
            else:
                for tf in msg.transforms:
                    frames.setdefault(tf.child_frame_id, []).append((tf.header.frame_id, tf.transform.translation.x,
                                                                     tf.transform.translation.y))
    check("/clock runs forward through the mission", len(clocks) > 100 and all(b >= a for a, b in zip(clocks, clocks[1:]))
          and clocks[-1] > 150, "%d stamps, last %s" % (len(clocks), clocks[-1:] or None))
    want_frames = {"agent_%d/base_link" % k for k in range(n)}
    check("TF: map -> agent_k/base_link for all %d agents" % n, want_frames <= set(frames) and
          all(p == "map" for k in want_frames for p, _, _ in frames.get(k, [("map", 0, 0)])),
          sorted(set(frames))[:5])
    ox, oy = sc["oc"]
    far = sorted(max(((x - ox) ** 2 + (y - oy) ** 2) ** 0.5 for _, x, y in v) for k, v in frames.items())
    check("TF: the team moves away from the OC (half the agents > 10 m from it)",
          len(far) == n and far[n // 2] > 10.0, far)
    if check("bag has exactly one /map message (latched)", len(maps) == 1, "got %d" % len(maps)):
        m = maps[0]
        h, w = want.shape
        check("/map size matches the image", (m.info.width, m.info.height) == (w, h))
        check("/map resolution and origin match the map YAML",
              abs(m.info.resolution - meta["resolution"]) < 1e-6 and
              abs(m.info.origin.position.x - meta["origin"][0]) < 1e-9 and
              abs(m.info.origin.position.y - meta["origin"][1]) < 1e-9 and m.header.frame_id == "map")
        got = np.array(m.data, dtype=np.int8).reshape(h, w)
        diff = int((got != want).sum())
        check("/map cells equal map_server's thresholding of the image", diff == 0, "%d cells differ" % diff)
    ids = {mk.id for mk in last_team.markers if mk.ns == "agents"} if last_team else set()
    check("team markers show all %d agents" % n, ids == set(range(n)), sorted(set(range(n)) - ids))
    ns = {mk.ns for mk in plan.markers} if plan else set()
    check("plan markers: segments, ids, OC, coverage, routes, meetings",
          {"segments", "segment_ids", "oc", "coverage", "routes", "meetings"} <= ns, sorted(ns))
    routes = [mk for mk in plan.markers if mk.ns == "routes"] if plan else []
    check("plan markers: one route per collector", len(routes) == collectors, len(routes))


def rviz_crashed(out):
    """RViz (a third-party process, on llvmpipe) killed by a signal."""
    return re.search(r"\[rviz-\d+\] process has died \[pid \d+, exit code -\d+", out) is not None


def with_rviz(label, run):
    """Runs `run` (True: done; False: RViz crashed) and once more if RViz
    crashed, discarding the first attempt's checks. RViz 1.14 under llvmpipe
    segfaulted in about 1 of 10 sessions on this machine, never twice in a
    row; gather's own processes are checked either way."""
    kept = len(results)
    if run():
        return
    discarded = results[kept:]
    del results[kept:]
    print("WARN %s: RViz crashed (SIGSEGV, its own process); the %d checks above from this attempt "
          "(%d FAIL) are discarded; running it once more" % (label, len(discarded), discarded.count(False)),
          flush=True)
    check("%s: RViz did not crash twice in a row" % label, run())


def map_topic_launch(path, args):
    """A launch file: map_publisher with maps/office.yaml on /map, and mission.launch with map_topic:=/map."""
    lines = ["<launch>",
             '  <node pkg="gather_oc" type="map_publisher" name="map_server" args="%s"/>' %
             os.path.join(REPO, "maps", "office.yaml"),
             '  <include file="$(find gather_oc)/launch/mission.launch">',
             '    <arg name="map_topic" value="/map"/>']
    lines += ['    <arg name="%s" value="%s"/>' % kv for kv in sorted(args.items())]
    lines += ["  </include>", "</launch>", ""]
    with open(path, "w") as f:
        f.write("\n".join(lines))
    return path


def check_results(out_dir, scenario, cycles, n):
    r = yaml.safe_load(open(os.path.join(out_dir, "mission.yaml")))
    check("results: status ok", r["status"] == "ok", r.get("failure"))
    g = r["goals"]
    per_request = yaml.safe_load(open(scenario)).get("mission", {}).get("goals_per_request", 40)
    check("results: every goal requested resolved", g["requested"] == cycles * per_request and
          g["delivered"] + g["expired"] + g["dropped"] == g["requested"], g)
    check("results: some goals delivered, none dropped", g["delivered"] > 0 and g["dropped"] == 0, g)
    check("results: %d agents, nothing carried at the end, no bad message" % n,
          len(r["agents"]) == n and all(x["carried"] == 0 and x["bad"] == 0 for x in r["agents"]))
    f = yaml.safe_load(open(os.path.join(out_dir, "fleet.yaml")))
    check("fleet: every agent ended by itself with status 0", f["status"] == "ok" and len(f["agents"]) == n and
          all(x["exit_status"] == 0 and x["ended"] == "by_itself" for x in f["agents"]), f["status"])
    return r


def same_as_in_process(out_dir, plan_dir, cycles, label):
    same_dir = out_dir + "_in_process"
    p = subprocess.run([GATHER, "run", plan_dir, "--cycles", str(cycles), "--out", same_dir],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
    if check("%s: gather run in one process on the same plan" % label, p.returncode == 0, p.stdout[-800:]):
        for name in ("goals.csv", "cycles.csv"):
            same = open(os.path.join(out_dir, name), "rb").read() == open(os.path.join(same_dir, name), "rb").read()
            check("%s: %s == gather run in one process (byte for byte)" % (label, name), same)


def quiet(out, label):
    check("%s: a quiet end (no 'REQUIRED process ... has died')" % label, "REQUIRED process" not in out, out[-1500:])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cycles", type=int, default=2)
    a = ap.parse_args()
    if os.environ.get("GATHER_NETNS") != "1":
        print("mission_e2e: run me inside tools/netns-run (LCM multicast must stay in a private namespace)",
              file=sys.stderr)
        return 2
    if not os.environ.get("DISPLAY"):
        print("mission_e2e: needs an X display (xvfb-run) for RViz", file=sys.stderr)
        return 2
    os.makedirs(SHOTS, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix="gather_e2e_")
    office = os.path.join(REPO, "maps", "office.scenario.yaml")
    office_a = os.path.abspath(os.path.join(REPO, "..", "shared", "maps", "ipa", "office_a.scenario.yaml"))
    n = yaml.safe_load(open(office))["team"]["agents"]

    plan = os.path.join(tmp, "office_pap4")
    subprocess.run([GATHER, "plan", office, "--config", "pap:4", "--association", "off", "--out", plan], check=True,
                   stdout=subprocess.DEVNULL, timeout=300)
    plan_a = os.path.join(tmp, "office_a_pap4")
    subprocess.run([GATHER, "plan", office_a, "--config", "pap:4", "--association", "off", "--out", plan_a], check=True,
                   stdout=subprocess.DEVNULL, timeout=300)
    out1 = os.path.join(tmp, "office")
    bag = os.path.join(out1, "mission.bag")

    def office_run():
        # 1. office, pap:4, RViz + rosbag, two screenshots.
        run = Launch(["scenario:=" + office, "plan:=" + plan, "cycles:=%d" % a.cycles, "rate:=12", "results_dir:=" + out1,
                      "rviz:=true", "record:=true", "close_on_end:=true"], os.path.join(tmp, "office.log"))
        try:
            started = run.wait_for(r"mission starts", 120)
            check("office: the mission starts", started, run.output()[-1500:])
            check("office: RViz shows up", wait_visible(os.path.join(tmp, "probe_office.png"), "office"))
            shot1 = screenshot_when_drawn(os.path.join(SHOTS, "office_pap4_early.png"), "office, early", 4)
            time.sleep(6.0)
            shot2 = screenshot(os.path.join(SHOTS, "office_pap4_later.png"))
            rc = run.wait(300)
            out = run.output()
        finally:
            run.close()
        if rviz_crashed(out):
            return False
        check("office: roslaunch exits 0 by itself", rc == 0, "status %s" % rc)
        quiet(out, "office")
        check("office: the OC prints its summary line", re.search(r"oc: mission done: pap Nc=4, %d cycles" % a.cycles, out),
              out[-1500:])
        check("office: the fleet reports every agent", "fleet: %d agents: all exited 0" % n in out, out[-1500:])
        check("office: RViz's view was fitted to the map", "rviz_view: view of the map on /map" in out, out[-1500:])
        check_results(out1, office, a.cycles, n)
        k = os.path.join(out1, "fleet.key")
        check("office: fleet traffic signed with a key made beside the results (mode 0600)",
              os.path.exists(k) and (os.stat(k).st_mode & 0o777) == 0o600 and "fleet traffic signed with key" in out,
              out[-1500:])
        same_as_in_process(out1, plan, a.cycles, "office")
        if check("office: bag recorded", os.path.exists(os.path.join(out1, "mission.bag"))):
            check_bag(os.path.join(out1, "mission.bag"), office, n, 4)
        check_screen("office, early", shot1, 4)
        check_screen("office, later", shot2, 4)
        oc = oc_pixel(shot1)
        if check("office: the OC is on screen", oc is not None):
            changed = np.abs(shot2 - shot1).sum(axis=2) > 60
            changed[:120, :] = False  # the status line and the tool bar
            ys, xs = np.nonzero(changed)
            dist = np.hypot(xs - oc[0], ys - oc[1])
            check("office: the picture changes far from the OC as the team moves (> 2000 px beyond 300 px of it)",
                  int((dist > 300).sum()) > 2000, int((dist > 300).sum()))

        return True

    def ended_by_ctrl_c(label, what, rc, out, shot):
        """The checks after an RViz session stopped with Ctrl-C; False when RViz crashed (retried)."""
        if rviz_crashed(out):
            return False
        check("%s: %s" % (label, what), rc == 0, "status %s" % rc)
        quiet(out, label)
        check_screen(label, shot, 4)
        return True

    def office_a_run():
        # 2. office_a, its own pap:4 plan: RViz fits this map too; Ctrl-C ends it.
        out2 = os.path.join(tmp, "office_a")
        # (No scenario:=: the plan names its own, office_a's.)
        run = Launch(["plan:=" + plan_a, "cycles:=1", "rate:=25", "results_dir:=" + out2,
                      "rviz:=true"], os.path.join(tmp, "office_a.log"))
        try:
            check("office_a: the mission starts", run.wait_for(r"mission starts", 120), run.output()[-1500:])
            check("office_a: RViz shows up", wait_visible(os.path.join(tmp, "probe.png"), "office_a"))
            time.sleep(3.0)
            shot = screenshot(os.path.join(SHOTS, "office_a_pap4.png"))
            done = run.wait_for(r"mission done", 120)
            check("office_a: the mission ends and the launch stays up with RViz", done and run.p.poll() is None,
                  run.output()[-1500:])
            rc = run.interrupt(30)
            out = run.output()
        finally:
            run.close()
        return ended_by_ctrl_c("office_a", "Ctrl-C ends the launch", rc, out, shot)

    def review_run():
        # 3. review.launch on the office bag.
        if os.path.exists(bag):
            run = Launch(["bag:=" + bag, "rate:=40", "start:=60"], os.path.join(tmp, "review.log"), "review.launch")
            try:
                check("review: the bag plays", run.wait_for(r"review_player: .*playing at 40x from 60 s", 60),
                      run.output()[-1500:])
                check("review: RViz's view was fitted to the map", run.wait_for(r"rviz_view: view of the map", 60),
                      run.output()[-1500:])
                check("review: RViz shows up", wait_visible(os.path.join(tmp, "probe.png"), "review"))
                time.sleep(1.0)
                shot = screenshot(os.path.join(SHOTS, "office_pap4_review.png"))
                ended = run.wait_for(r"the bag has ended", 120)
                time.sleep(2.0)
                check("review: RViz stays open after the bag ends", ended and run.p.poll() is None, run.output()[-1500:])
                rc = run.interrupt(30)
                out = run.output()
            finally:
                run.close()
            return ended_by_ctrl_c("review", "Ctrl-C ends it", rc, out, shot)
        return True

    # 0. The default mission, as `make run` starts it (the Makefile's
    # SCENARIO; one cycle): the OC plans the scenario, its best plan has
    # collectors some workers hand their data to, and the summary counts
    # the goals that came through a collector.
    default = os.path.join(REPO, re.search(r"^SCENARIO \?= (\S+)", open(os.path.join(REPO, "Makefile")).read(),
                                           re.M).group(1))
    out0 = os.path.join(tmp, "default")
    rc, out = roslaunch(["scenario:=" + default, "cycles:=1", "results_dir:=" + out0], 600)
    check("default mission (%s): roslaunch exits 0" % os.path.basename(default), rc == 0, out[-1500:])
    r = check_results(out0, default, 1, yaml.safe_load(open(default))["team"]["agents"])
    plan0 = yaml.safe_load(open(os.path.join(out0, "plan", "plan.yaml")))
    active = {x["collector"] for x in plan0["agents"] if x["role"] == "worker" and x["collector"] >= 0}
    check("default mission: the planner's best plan has collectors, %d of them active" % len(active),
          plan0["collectors"] >= 1 and len(active) >= 1, plan0["collectors"])
    p = subprocess.run([sys.executable, os.path.join(REPO, "tools", "mission_summary.py"), out0],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
    m = re.search(r"^carried  (\d+) of (\d+) delivered goals came through a collector .* by (\d+) of the plan's "
                  r"(\d+) collectors", p.stdout, re.M)
    check("default mission: the summary says how many goals came through a collector (some did)",
          p.returncode == 0 and m is not None and int(m.group(1)) > 0 and int(m.group(2)) == r["goals"]["delivered"]
          and int(m.group(4)) == plan0["collectors"], p.stdout[:1500])

    with_rviz("office", office_run)
    with_rviz("office_a", office_a_run)
    with_rviz("review", review_run)

    # 3b. Paths relative to where the user is: the bag by its name in its directory.
    if os.path.exists(bag):
        run = Launch(["bag:=mission.bag", "rate:=100", "rviz:=false"], os.path.join(tmp, "review_rel.log"),
                     "review.launch", cwd=out1)
        try:
            ended = run.wait_for(r"the bag has ended", 120)
            rc = run.interrupt(30)
            out = run.output()
        finally:
            run.close()
        check("review: a bag path relative to where roslaunch runs", ended and rc == 0, out[-1500:])

    # 3c. Ctrl-C in the middle of a mission, results_dir relative to where roslaunch runs.
    run = Launch(["plan:=" + plan, "cycles:=2", "rate:=5", "results_dir:=stopped", "record:=true"],
                 os.path.join(tmp, "stopped.log"), cwd=tmp)
    try:
        check("stop: the mission starts", run.wait_for(r"mission starts", 120), run.output()[-1500:])
        time.sleep(3.0)
        t0 = time.time()
        rc = run.interrupt(30)
        took = time.time() - t0
        out = run.output()
    finally:
        run.close()
    stopped = os.path.join(tmp, "stopped")
    check("stop: Ctrl-C ends the launch within 5 s, quietly", rc == 0 and took < 5.0 and "REQUIRED process" not in out,
          "status %s after %.1f s: %s" % (rc, took, out[-800:]))
    check("stop: the OC says why in one line and writes mission.yaml (incomplete)",
          "before the stop; %s/mission.yaml" % stopped in out and
          yaml.safe_load(open(os.path.join(stopped, "mission.yaml")))["status"] == "incomplete", out[-800:])
    check("stop: the bag is where the results are (results_dir:=stopped, relative)",
          os.path.exists(os.path.join(stopped, "mission.bag")), sorted(os.listdir(stopped)) if os.path.isdir(stopped)
          else "no %s" % stopped)

    # 4. The map from a map topic, published as map_server does.
    nomap = os.path.join(tmp, "nomap.scenario.yaml")
    with open(office) as f, open(nomap, "w") as g:
        g.write("".join(line for line in f if not line.startswith("map:")))
    out4 = os.path.join(tmp, "map_topic")
    launch = map_topic_launch(os.path.join(tmp, "map_topic.launch"), {"scenario": nomap, "cycles": "1",
                                                                      "results_dir": out4})
    run = Launch([], os.path.join(tmp, "map_topic.log"), launch)
    try:
        rc = run.wait(300)
        out = run.output()
    finally:
        run.close()
    check("map topic: roslaunch exits 0", rc == 0, out[-1500:])
    quiet(out, "map topic")
    check("map topic: the OC took the map from /map", "oc: map 1200x700 cells of 0.050 m from /map" in out, out[-1500:])
    check("map topic: saved as map_server files for the agents",
          all(os.path.exists(os.path.join(out4, "map", x)) for x in ("map.yaml", "map.pgm", "scenario.yaml")))
    if os.path.exists(os.path.join(out4, "mission.yaml")):
        check_results(out4, office, 1, n)
        best = os.path.join(tmp, "office_best")
        subprocess.run([GATHER, "plan", office, "--out", best], check=True, stdout=subprocess.DEVNULL, timeout=300)
        same_as_in_process(out4, best, 1, "map topic (vs the scenario's own map)")

    # 4b. A map topic with a plan made for other settings: refused, exit 2.
    other = os.path.join(tmp, "other_seed.scenario.yaml")
    with open(nomap) as f, open(other, "w") as g:
        g.write(f.read().replace("  seed: 1", "  seed: 7"))
    launch = map_topic_launch(os.path.join(tmp, "map_topic_bad.launch"),
                              {"scenario": other, "plan": plan, "results_dir": os.path.join(tmp, "map_topic_bad")})
    out = subprocess.run(["roslaunch", launch], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                         timeout=120).stdout
    check("map topic with a plan for other settings: the OC names the plan and exits 2",
          "whose OC, team, radio or mission differ" in out and re.search(r"exit code 2, cmd \S*oc_node", out), out[-1500:])

    # 5. The usual tools.
    if os.path.exists(bag):
        for topic in ("/gather/cycle", "/gather/status", "/gather/agents"):
            p = subprocess.run(["rostopic", "echo", "-p", "-b", bag, topic], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, timeout=120)
            lines = p.stdout.strip().splitlines()
            check("rostopic echo -p %s (from the bag)" % topic, p.returncode == 0 and len(lines) >= 2 and
                  lines[0].startswith("%time"), p.stdout[-600:])
        p = subprocess.run(["rostopic", "echo", "-p", "-b", bag, "/gather/cycle"], stdout=subprocess.PIPE, text=True)
        header = p.stdout.splitlines()[0].split(",") if p.stdout else []
        check("rostopic echo -p /gather/cycle: numeric columns a plot can read",
              {"field.delivered", "field.refresh_mean", "field.refresh_max", "field.expired"} <= set(header), header)
        p = subprocess.run(["rosbag", "info", bag], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        check("rosbag info", p.returncode == 0 and "/gather/team_markers" in p.stdout, p.stdout[-600:])
    p = subprocess.run(["rosrun", "gather_core", "gather", "--help"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True)
    check("rosrun gather_core gather --help", p.returncode == 0 and "usage" in p.stdout.lower(), p.stdout[-600:])

    # 5c. Faults on the launch (issue: faults): 20% loss, worker 9 killed
    # (kill:=) and worker 8 crashed and started again from its journal
    # (restart:=; fleet_node respawns it) on office pap:4 with busy
    # collectors; the same goals as gather run in one process.
    busy = os.path.join(tmp, "office_pap4_busy")
    subprocess.run([GATHER, "plan", office, "--config", "pap:4", "--association", "off", "--out", busy], check=True,
                   stdout=subprocess.DEVNULL, timeout=300)
    faults_dir = os.path.join(tmp, "faults")
    flags = ["cycles:=3", "loss:=0.2", "kill:=9@150", "restart:=8@120"]
    rc, out = roslaunch(["plan:=" + busy, "results_dir:=" + faults_dir] + flags, timeout=300)
    if check("faults: roslaunch with kill:= and restart:= exits 0", rc == 0, out[-1500:]):
        r = yaml.safe_load(open(os.path.join(faults_dir, "mission.yaml")))
        check("faults: status ok, agent 9 declared dead after its kill",
              r["status"] == "ok" and [(f["agent"], f["declared_dead_at"] > 150) for f in r["faults"]] == [(9, True)],
              str(r.get("faults")))
        f = {x["id"]: x for x in yaml.safe_load(open(os.path.join(faults_dir, "fleet.yaml")))["agents"]}
        check("faults: fleet.yaml: 9 killed as asked, 8 started again once and exited 0",
              f[9]["killed_as_asked"] and f[8]["restarts"] == 1 and f[8]["exit_status"] == 0, str((f[8], f[9])))
        same_dir = faults_dir + "_in_process"
        p = subprocess.run([GATHER, "run", busy, "--out", same_dir, "--cycles", "3", "--loss", "0.2", "--kill", "9@150",
                            "--restart", "8@120"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
        if check("faults: gather run in one process with the same faults", p.returncode == 0, p.stdout[-800:]):
            for name in ("goals.csv", "cycles.csv", "faults.csv"):
                same = open(os.path.join(faults_dir, name), "rb").read() == open(os.path.join(same_dir, name), "rb").read()
                check("faults: %s == gather run in one process (byte for byte)" % name, same)

    # 6. Bad input through roslaunch: the OC exits 2 with one line.
    bad_dir = os.path.join(tmp, "bad")
    missing = os.path.join(tmp, "no_such.scenario.yaml")
    rc, out = roslaunch(["scenario:=" + missing, "results_dir:=" + bad_dir], timeout=60)
    check("bad scenario: OC reports the file on one line", ("oc_node: %s: cannot open file" % missing) in out,
          out[-1500:])
    check("bad scenario: OC exits with status 2", re.search(r"process has died \[pid \d+, exit code 2, cmd \S*oc_node",
                                                            out) is not None, out[-1500:])
    check("bad scenario: no results file", not os.path.exists(os.path.join(bad_dir, "mission.yaml")))
    rc, out = roslaunch(["scenario:=" + office, "plan:=" + os.path.join(tmp, "no_plan"), "results_dir:=" + bad_dir],
                        timeout=60)
    check("bad plan: OC names the directory and exits 2",
          ("oc_node: %s: no such plan directory" % os.path.join(tmp, "no_plan")) in out and
          re.search(r"exit code 2, cmd \S*oc_node", out) is not None, out[-1500:])

    # A plan alone that is not there (scenario auto): the OC names it; a
    # scenario given with another scenario's plan: the OC says so.
    rc, out = roslaunch(["plan:=" + os.path.join(tmp, "no_plan"), "results_dir:=" + bad_dir], timeout=60)
    check("a plan alone that is not there: OC names it and exits 2",
          re.search(r"oc_node: %s/plan\.yaml: " % re.escape(os.path.join(tmp, "no_plan")), out) is not None and
          re.search(r"exit code 2, cmd \S*oc_node", out) is not None, out[-1500:])
    rc, out = roslaunch(["scenario:=" + office, "plan:=" + plan_a, "results_dir:=" + bad_dir], timeout=60)
    check("a scenario given with another scenario's plan: OC says so and exits 2",
          "was planned for scenario" in out and re.search(r"exit code 2, cmd \S*oc_node", out) is not None,
          out[-1500:])

    # Agent processes that die at once (a bad binary, a crash): fleet_node
    # tells the OC (/gather/fleet/ended), which stops within seconds with
    # one line naming them and their exit status, not after 60 s for READY.
    dying = os.path.join(tmp, "dying_agent.sh")
    with open(dying, "w") as f:
        f.write("#!/bin/bash\nexit 3\n")
    os.chmod(dying, 0o755)
    t0 = time.time()
    rc, out = roslaunch(["scenario:=" + office, "plan:=" + plan, "agent_bin:=" + dying, "results_dir:=" + bad_dir],
                        timeout=120)
    took = time.time() - t0
    check("dying agents: the launch ends within 15 s (%.1f s)" % took, took < 15, out[-1500:])
    check("dying agents: the OC names them and their exit status and exits 1",
          re.search(r"oc_node: .*ended before saying READY: 0 \(status 3\)", out) is not None and
          re.search(r"exit code 1, cmd \S*oc_node", out) is not None, out[-1500:])

    # A key others can read: the OC refuses it (one line, status 2).
    open_key = os.path.join(tmp, "open.key")
    subprocess.run([GATHER, "keygen", open_key], check=True, stdout=subprocess.DEVNULL)
    os.chmod(open_key, 0o644)
    rc, out = roslaunch(["scenario:=" + office, "plan:=" + plan, "key_file:=" + open_key, "results_dir:=" + bad_dir],
                        timeout=60)
    check("bad key file: OC says chmod 600 and exits 2", "chmod 600" in out and
          re.search(r"exit code 2, cmd \S*oc_node", out) is not None, out[-1500:])

    print("screenshots: %s" % ", ".join(sorted(os.path.join(SHOTS, f) for f in os.listdir(SHOTS))))
    failed = results.count(False)
    print("%d passed, %d failed" % (len(results) - failed, failed))
    if not failed:
        shutil.rmtree(tmp, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
