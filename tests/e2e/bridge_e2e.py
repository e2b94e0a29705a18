#!/usr/bin/env python3
"""A team on robots that run ROS and move_base (docs/robots.md, "A robot that
runs ROS"): run me inside tools/netns-run with the workspace sourced.

Two robots, each `roslaunch gather_oc robot.launch` (its agent with --motion
lcm, and robot_bridge) in its own ROS namespace, each with move_base's
interface served by world_move_base on one of gather_world's MRPT robots
(goals on move_base_simple/goal, status on move_base/status, its pose on
/tf; gather_world plans the robot's way). The OC is `roslaunch gather_oc
mission.launch agents:=external robots:=external clock:=wall record:=true`:
it starts no agent, the robots' launches do, and its views go into a bag.
Agent 0's clock is put 2.5 s off. Checks: the mission completes and every
goal ends in a final state, with at least half as many goals
delivered through real ROS topics as with the agents driving the same
robots directly; each move_base took goals from its bridge; the agents
ended by themselves and their launches with them; the bag holds the OC's
views; robot_bridge's and `gather run --agents external`'s bad parameters
give one line and status 2.
"""
import argparse
import csv
import os
import re
import signal
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEVEL = os.path.join(REPO, "catkin_ws", "devel", "lib")
FAILURES = []
FINAL = {"delivered", "expired", "dropped_overflow", "unreachable"}
RATE = 5.0  # mission seconds per wall second (gather_world's robots keep up)
CYCLES = 2


def check(name, ok, detail=""):
    print(("PASS " if ok else "FAIL ") + name + ("" if ok or not detail else "\n     " + detail.replace("\n", "\n     ")))
    if not ok:
        FAILURES.append(name)
    return ok


def run(args, timeout=120):
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def stop(p):
    if p.poll() is None:
        p.send_signal(signal.SIGINT)
        try:
            p.wait(15)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()


def check_bag(path, goals_csv):
    """mission.launch record:=true with the agents on the robots: the OC's views, on the wall clock."""
    if not check("the OC's views recorded (%s)" % path, os.path.exists(path)):
        return
    import rosbag  # Debian's python3-rosbag (gather_msgs types come from the bag's own definitions)
    bag = rosbag.Bag(path)
    topics = bag.get_type_and_topic_info().topics
    want = ["/map", "/tf", "/gather/plan_markers", "/gather/team_markers", "/gather/status", "/gather/agent_1/pose"]
    check("the bag holds the OC's views", all(t in topics for t in want),
          "missing: %s" % [t for t in want if t not in topics])
    statuses = [m for _, m, _ in bag.read_messages(topics=["/gather/status"])]
    delivered = sum(r["state"] == "delivered" for r in csv.DictReader(open(goals_csv)))
    check("its last status says done, %d delivered (goals.csv: %d)" % (statuses[-1].delivered if statuses else -1,
                                                                      delivered),
          statuses and statuses[-1].state == "done" and statuses[-1].delivered == delivered)
    bag.close()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gather", default=os.path.join(DEVEL, "gather_core", "gather"))
    ap.add_argument("--bridge", default=os.path.join(DEVEL, "gather_oc", "robot_bridge"))
    ap.add_argument("--move-base", dest="move_base", default=os.path.join(DEVEL, "gather_oc", "world_move_base"))
    ap.add_argument("--world", default=os.path.join(DEVEL, "gather_world", "gather_world"))
    ap.add_argument("--keep", default="")
    a = ap.parse_args()
    if os.environ.get("GATHER_NETNS") != "1":
        print("bridge_e2e: run me inside tools/netns-run (LCM multicast and the ROS master stay in a private namespace)",
              file=sys.stderr)
        return 2
    tmp = a.keep or tempfile.mkdtemp(prefix="gather_bridge_e2e_")
    os.makedirs(tmp, exist_ok=True)

    key = os.path.join(tmp, "fleet.key")
    if not os.path.exists(key):
        run([a.gather, "keygen", key])
    plan = os.path.join(tmp, "plan")
    scenario = os.path.join(REPO, "tests", "oc", "fixtures", "office2.scenario.yaml")
    rc, out, err = run([a.gather, "plan", scenario,
                        "--config", "pap:0", "--out", plan])
    if not check("plan office with two robots", rc == 0, err):
        return 1
    url = "udpm://239.255.76.67:7667?ttl=1"
    # The OC alone (--agents external) only with robots of their own on the wall clock: else one line, status 2.
    for extra, needle in ((["--robots", "external", "--clock", "wall", "--agents", "bogus"], "--agents must be"),
                          (["--agents", "external"], "--agents external needs --robots external --clock wall"),
                          (["--robots", "external", "--clock", "wall", "--agents", "external", "--kill", "0@10"],
                           "starts no agent")):
        rc, _, err = run([a.gather, "run", plan, "--out", os.path.join(tmp, "bad"), "--lcm", "--key-file", key] + extra)
        check("gather run %s: status 2, one line" % " ".join(extra), rc == 2 and err.count("\n") == 1 and needle in err,
              "status %d: %s" % (rc, err))
    # The master (on a real team: the robots' own ROS), then each robot's
    # launch in its own namespace, as on its own computer.
    master = subprocess.Popen(["roscore", "-p", "11311"], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    time.sleep(4.0)  # roscore sets the run id every launch then joins
    logs, launches = [], []
    for k in range(2):
        logs.append(open(os.path.join(tmp, "roslaunch%d.log" % k), "w"))  # a file: a full pipe would stop the agent
        launches.append(subprocess.Popen(
            ["roslaunch", "--screen", "gather_oc", "robot.launch", "__ns:=r%d" % k, "id:=%d" % k, "plan:=" + plan,
             "key_file:=" + key, "lcm_url:=" + url, "base_frame:=r%d/base_link" % k,
             "journal:=" + os.path.join(tmp, "journal%d" % k), "pose_rate:=20", "clock_skew:=%g" % (2.5 if k == 0 else 0)],
            stdout=logs[k], stderr=subprocess.STDOUT, text=True))
    time.sleep(3.0)
    if any(p.poll() is not None for p in launches):
        for f in logs:
            f.close()
        check("roslaunch gather_oc robot.launch, one per robot, starts", False,
              "".join(open(os.path.join(tmp, "roslaunch%d.log" % k)).read()[-2000:] for k in range(2)))
        for p in launches + [master]:
            stop(p)
        return 1
    # move_base on each robot: world_move_base on gather_world's robots (MRPT).
    world_url = "udpm://239.255.76.67:7673?ttl=0"  # a port of its own: LCM hears every group on its port
    fakes = [subprocess.Popen([a.world, "--plan", plan, "--lcm-url", url, "--robot-url", world_url, "--key-file", key],
                              stdout=open(os.path.join(tmp, "world.log"), "w"), stderr=subprocess.STDOUT)]
    for k in range(2):
        fakes.append(subprocess.Popen([a.move_base, "__name:=move_base", "__ns:=r%d" % k, "_agent:=%d" % k,
                                       "_robot_url:=" + world_url, "_key_file:=" + key,
                                       "_base_frame:=r%d/base_link" % k],
                                      stdout=open(os.path.join(tmp, "move_base%d.log" % k), "w"),
                                      stderr=subprocess.STDOUT))
    out_dir = os.path.join(tmp, "run")
    try:
        # Bad parameters: one line naming the parameter, status 2 (the parameters go through the master).
        for params, needle in ((["_agent:=-1", "_insecure:=true"], "~agent"),
                               (["_agent:=0", "_insecure:=true", "_pose_rate:=abc"], "~pose_rate"),
                               (["_agent:=0", "_insecure:=true", "_pose_rate:=500"], "~pose_rate"),
                               (["_agent:=0"], "~key_file")):
            rc, out, err = run([a.bridge, "__name:=bad_bridge_%d" % len(params + [needle]) + needle[1:]] + params,
                               timeout=30)
            check("robot_bridge %s: status 2, one line naming %s" % (" ".join(params), needle),
                  rc == 2 and err.count("\n") == 1 and needle in err, "status %d: %s" % (rc, err))

        oc_node = os.path.join(DEVEL, "gather_oc", "oc_node")
        for params, needle in ((["_agents:=bogus"], "~agents must be"),
                               (["_agents:=external", "_robots:=external"], "~agents external needs"),
                               (["_agents:=external", "_robots:=external", "_clock:=wall", "_kill:=0@10"],
                                "starts no agent")):
            rc, out, err = run([oc_node, scenario, plan, "__name:=bad_oc_%d" % len(params)] + params, timeout=30)
            check("oc_node %s: status 2, one line" % " ".join(params),
                  rc == 2 and err.count("\n") == 1 and needle in err, "status %d: %s" % (rc, err))
        rc, oc_out, oc_err = run(
            ["roslaunch", "--screen", "gather_oc", "mission.launch", "scenario:=" + scenario, "plan:=" + plan,
             "agents:=external", "robots:=external", "clock:=wall", "rate:=%g" % RATE, "cycles:=%d" % CYCLES,
             "lcm_url:=" + url, "key_file:=" + key, "results_dir:=" + out_dir, "record:=true"], timeout=600)
        # roslaunch ends 0 whatever its nodes did: the OC's own word is its summary line.
        rc = rc if rc != 0 or "oc: mission done" in oc_out + oc_err else 1
        ended = []
        for p in launches:
            try:
                ended.append(p.wait(timeout=30) is not None)  # each agent ends with the mission, its launch with it
            except subprocess.TimeoutExpired:
                ended.append(False)
    finally:
        for p in fakes:
            stop(p)
        for p in launches:
            stop(p)
        stop(master)
        for f in logs:
            f.close()
    launch_out = "".join(open(os.path.join(tmp, "roslaunch%d.log" % k)).read() for k in range(2))
    if not check("the OC ran the mission with the robots' agents (status %d)" % rc, rc == 0,
                 oc_out[-1000:] + oc_err[-1500:] + "\n--- roslaunch:\n" + launch_out[-3000:]):
        return 1
    check("the OC started no agent, it waited for them",
          "waiting up to 300 s for the 2 agents" in oc_out + oc_err and "fleet_node" not in oc_out + oc_err,
          (oc_out + oc_err)[:1500])
    check_bag(os.path.join(out_dir, "mission.bag"), os.path.join(out_dir, "goals.csv"))
    rows = list(csv.DictReader(open(os.path.join(out_dir, "goals.csv"))))
    states = {}
    for r in rows:
        states[r["state"]] = states.get(r["state"], 0) + 1
    check("every goal in a final state %s" % states, rows and set(states) <= FINAL)
    by = {k: sum(r["measured_by"] == str(k) and r["state"] == "delivered" for r in rows) for k in range(2)}
    # Beside the same robots driven by their agents directly (gather run --robots mrpt, in one process).
    ref = os.path.join(tmp, "direct")
    rc, _, err = run([a.gather, "run", plan, "--out", ref, "--robots", "mrpt", "--cycles", str(CYCLES)])
    if check("the same plan on gather_world's robots without ROS", rc == 0, err[-800:]):
        direct = sum(r["state"] == "delivered" for r in csv.DictReader(open(os.path.join(ref, "goals.csv"))))
        got = states.get("delivered", 0)
        check("delivered through robot_bridge and move_base: %d of %d goals (by robot %s); with the agents driving "
              "gather_world's robots directly (lockstep): %d" % (got, len(rows), by, direct),
              got >= 1 and 2 * got >= direct)
    for k in range(2):
        check("robot_bridge %d started on the robot interface" % k,
              re.search(r"robot_bridge %d: the robot interface on udpm://239.255.76.67:7669\?ttl=0, move_base on "
                        r"/r%d/move_base_simple/goal" % (k, k), launch_out) is not None)
        check("agent %d ended by itself at the mission's end, and its launch with it" % k,
              ended[k] and re.search(r"REQUIRED process \[r%d/agent_%d-\d+\] has died!\s*process has finished cleanly"
                                     % (k, k), launch_out) is not None)
    for k in range(2):
        log = open(os.path.join(tmp, "move_base%d.log" % k)).read()
        goals = len(re.findall(r"world_move_base %d: world-%d-\d+ (succeeded|preempted|aborted)" % (k, k), log))
        check("robot %d's move_base took %d goals from robot_bridge" % (k, goals), goals >= 2, log[-500:])
    m = re.search(r"gather_agent 0: clock offset to the OC ([-+0-9.]+) s", launch_out)
    check("agent 0 (its clock 2.5 s off) measured its offset (%s s)" % (m.group(1) if m else "?"),
          m is not None and abs(float(m.group(1)) + 2.5) < 0.05)
    print("bridge_e2e: %d failed" % len(FAILURES) if FAILURES else "bridge_e2e: all passed")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
