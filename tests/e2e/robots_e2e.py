#!/usr/bin/env python3
"""End-to-end test of the team on robots (docs/robots.md), without ROS:

- gather_world's MRPT robots behind the robot interface, the agents in one
  process (gather run --robots mrpt): twice the same run, byte for byte
  (gather_world is deterministic on the lockstep clock), and every goal in
  exactly one final state, none delivered twice;
- the same plan and seed with one gather_agent process per agent and
  gather_world over LCM (--lcm): the same goals.csv, byte for byte;
- the example robot driver in Python (src/gather_agent/examples/robot_driver.py,
  the lcm package from PyPI and the types of lcm-gen --python) driving a
  whole team over LCM on the wall clock (gather run --robots external): the
  mission ends, goals are delivered, every goal in one final state; each
  agent process on a robot stays within 16 MB resident;
- with --launch, roslaunch gather_oc mission.launch robots:=mrpt laser:=true
  record:=true on the same plan and seed: the same goals.csv as over LCM,
  byte for byte (the scans change nothing), and the bag holds every robot's
  laser scans (sensor_msgs/LaserScan) and their markers;
- bad input: a world YAML with a bad field, gather_world without a plan:
  one line, exit status 2.

Must run inside a private network namespace (LCM multicast):
  tools/netns-run bash -c 'source catkin_ws/devel/setup.bash &&
      python3 tests/e2e/robots_e2e.py --pylcm build/pylcm --launch'
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile
import time

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DEVEL = os.path.join(REPO, "catkin_ws", "devel", "lib")
TEAM = 8
FINAL = {"delivered", "expired", "dropped_overflow", "lost_with_agent", "unreachable"}
results = []


def check(name, ok, detail=""):
    results.append(ok)
    print("%s %s%s" % ("ok  " if ok else "FAIL", name, "" if ok else ": " + detail), flush=True)
    return ok


def run(args, timeout=600, env=None):
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout, env=env)
    return p.returncode, p.stdout, p.stderr


def goals(path):
    with open(os.path.join(path, "goals.csv")) as f:
        return list(csv.DictReader(f))


def accounted(name, path):
    """Every goal in one final state, none delivered twice, some delivered."""
    rows = goals(path)
    states = {r["state"] for r in rows}
    check(name + ": every goal in one final state %s" % sorted(states), states <= FINAL, str(states - FINAL))
    ids = [r["goal"] for r in rows]
    check(name + ": each goal once in goals.csv", len(ids) == len(set(ids)))
    delivered = sum(r["state"] == "delivered" for r in rows)
    check(name + ": goals delivered (%d of %d)" % (delivered, len(rows)), delivered > 0)
    return delivered


def scans(bag_path):
    """laser:=true: every robot's scans in the bag, with returns, in its laser's frame."""
    import rosbag
    topics = ["/gather/agent_%d/scan" % k for k in range(TEAM)]
    per, returns, frames, markers = {t: 0 for t in topics}, 0, set(), 0
    with rosbag.Bag(bag_path) as bag:
        for topic, msg, _ in bag.read_messages(topics=topics + ["/gather/laser_markers"]):
            if topic == "/gather/laser_markers":
                markers += 1
                continue
            per[topic] += 1
            frames.add(msg.header.frame_id)
            returns += sum(1 for r in msg.ranges if r <= msg.range_max)
    check("laser:=true: every robot's scans in the bag (%d to %d each)" % (min(per.values()), max(per.values())),
          min(per.values()) > 0, str(per))
    check("laser:=true: scans in frames agent_<k>/laser, with returns (%d)" % returns,
          frames == {"agent_%d/laser" % k for k in range(TEAM)} and returns > 0, str(sorted(frames)))
    check("laser:=true: laser markers in the bag (%d)" % markers, markers > 0)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--gather", default=os.path.join(DEVEL, "gather_core", "gather"))
    p.add_argument("--world", default=os.path.join(DEVEL, "gather_world", "gather_world"))
    p.add_argument("--agent", default=os.path.join(DEVEL, "gather_agent", "gather_agent"))
    p.add_argument("--pylcm", required=True, help="the lcm package and the generated gather_lcm types (make pylcm)")
    p.add_argument("--cycles", type=int, default=1)
    p.add_argument("--launch", action="store_true", help="also through mission.launch (a sourced ROS workspace)")
    a = p.parse_args()
    if os.environ.get("GATHER_NETNS") != "1":
        sys.exit("robots_e2e: run it inside tools/netns-run (LCM multicast)")
    tmp = tempfile.mkdtemp(prefix="gather_robots_e2e_")
    # maps/office with a team of 6 (21 processes a tick over LCM would make
    # this test slow, not better).
    office = os.path.join(REPO, "maps", "office.scenario.yaml")
    scenario = os.path.join(tmp, "office6.scenario.yaml")
    text = open(office).read().replace("map: office.yaml", "map: " + os.path.join(REPO, "maps", "office.yaml"))
    with open(scenario, "w") as f:
        f.write(text.replace("agents: 20", "agents: %d" % TEAM).replace("collectors: [0, 8]", "collectors: [0, 2]"))
    plan = os.path.join(tmp, "plan")
    rc, _, err = run([a.gather, "plan", scenario, "--config", "bap:0", "--out", plan])
    if not check("plan office (a team of %d) bap:0" % TEAM, rc == 0, err[-2000:]):
        return 1
    key = os.path.join(tmp, "fleet.key")
    run([a.gather, "keygen", key])

    # gather_world in one process, twice: the same run.
    one, again = os.path.join(tmp, "one"), os.path.join(tmp, "again")
    t0 = time.time()
    rc, out, err = run([a.gather, "run", plan, "--out", one, "--cycles", str(a.cycles), "--robots", "mrpt"])
    check("gather run --robots mrpt completes (%.0f s)" % (time.time() - t0), rc == 0, err[-2000:])
    rc2, _, err2 = run([a.gather, "run", plan, "--out", again, "--cycles", str(a.cycles), "--robots", "mrpt"])
    if rc == 0 and rc2 == 0:
        check("gather_world is deterministic: the same goals.csv twice",
              open(os.path.join(one, "goals.csv")).read() == open(os.path.join(again, "goals.csv")).read())
        accounted("robots in one process", one)
        agents = list(csv.DictReader(open(os.path.join(one, "agents.csv"))))
        legs = sum(int(r["legs"]) for r in agents)
        check("agents.csv counts the robots' legs (%d)" % legs, legs > 0)

    # Over LCM: one process per agent, gather_world beside them.
    # The agents run under a wrapper that records their peak resident memory.
    lcm = os.path.join(tmp, "lcm")
    wrapper = os.path.join(tmp, "agent_with_memory.sh")
    with open(wrapper, "w") as f:
        f.write("#!/bin/bash\n# $2 is the agent id\nexec /usr/bin/time -f %%M -o %s/mem.$2 %s \"$@\"\n" % (tmp, a.agent))
    os.chmod(wrapper, 0o755)
    t0 = time.time()
    rc, out, err = run([a.gather, "run", plan, "--out", lcm, "--cycles", str(a.cycles), "--robots", "mrpt", "--lcm",
                        "--key-file", key, "--agent-bin", wrapper])
    if check("gather run --robots mrpt --lcm completes (%.0f s)" % (time.time() - t0), rc == 0, err[-2000:]) and \
            os.path.exists(os.path.join(one, "goals.csv")):
        check("over LCM: goals.csv byte-identical to one process",
              open(os.path.join(lcm, "goals.csv")).read() == open(os.path.join(one, "goals.csv")).read())
        mem = sorted(int(open(os.path.join(tmp, f)).read().split()[-1]) for f in os.listdir(tmp) if f.startswith("mem."))
        if check("peak memory of all %d agents on robots recorded" % TEAM, len(mem) == TEAM, str(mem)):
            print("     agent (--motion lcm) peak resident memory [MB]: median %.1f, max %.1f"
                  % (mem[len(mem) // 2] / 1024.0, mem[-1] / 1024.0))
            check("every agent on a robot within 16 MB resident", mem[-1] <= 16 * 1024, "max %d kB" % mem[-1])

    # The same through roslaunch gather_oc mission.launch robots:=mrpt.
    if a.launch:
        launched = os.path.join(tmp, "launch")
        t0 = time.time()
        rc, out, err = run(["roslaunch", "--log", "gather_oc", "mission.launch", "plan:=" + plan,
                            "scenario:=" + scenario, "robots:=mrpt", "laser:=true", "record:=true",
                            "cycles:=%d" % a.cycles, "results_dir:=" + launched, "key_file:=" + key])
        status = ""
        if os.path.exists(os.path.join(launched, "mission.yaml")):
            status = open(os.path.join(launched, "mission.yaml")).read()
        if check("mission.launch robots:=mrpt completes (%.0f s)" % (time.time() - t0),
                 rc == 0 and "status: ok" in status, (out + err)[-2000:]) and os.path.exists(os.path.join(lcm, "goals.csv")):
            check("mission.launch robots:=mrpt: goals.csv byte-identical to gather run --robots mrpt --lcm",
                  open(os.path.join(launched, "goals.csv")).read() == open(os.path.join(lcm, "goals.csv")).read())
            fleet = open(os.path.join(launched, "fleet.yaml")).read()
            check("fleet.yaml: every process exited 0", "status: ok" in fleet, fleet[:500])
            scans(os.path.join(launched, "mission.bag"))

    # The example driver in Python drives the team, on the wall clock.
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.abspath(a.pylcm) + (":" + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    driver_py = os.path.join(REPO, "src", "gather_agent", "examples", "robot_driver.py")
    oc = [float(v) for v in open(os.path.join(REPO, "maps", "office.scenario.yaml")).read().split("oc:")[1]
          .split("]")[0].strip(" [").split(",")]
    rate = 4
    driver = subprocess.Popen([sys.executable, driver_py, "--ids", "0-%d" % (TEAM - 1), "--start", "%g,%g" % (oc[0], oc[1]),
                               "--key-file", key, "--time-scale", str(rate), "--duration", "400"],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    ext = os.path.join(tmp, "external")
    t0 = time.time()
    rc, out, err = run([a.gather, "run", plan, "--out", ext, "--cycles", str(a.cycles), "--robots", "external",
                        "--lcm", "--key-file", key, "--clock", "wall", "--rate", str(rate)])
    driver.terminate()
    d_out, d_err = driver.communicate(timeout=30)
    if check("the team on the Python example driver completes (%.0f s)" % (time.time() - t0), rc == 0,
             err[-2000:] + d_err[-1000:]):
        accounted("on the Python driver", ext)
    check("the driver ran until told to stop", driver.returncode in (0, -15), d_err[-1000:])

    # Bad input: one line, exit status 2.
    bad = os.path.join(tmp, "bad_world.yaml")
    with open(bad, "w") as f:
        f.write("navigator: {paths: 3}\n")
    rc, out, err = run([a.gather, "run", plan, "--out", os.path.join(tmp, "bad"), "--robots", "mrpt",
                        "--world-config", bad])
    check("a bad world YAML: exit 2, one line naming the field",
          rc == 2 and "navigator.paths = 3" in err and len(err.strip().splitlines()) == 1, "%d %r" % (rc, err))
    rc, out, err = run([a.world, "--config", bad])
    check("gather_world without a plan: exit 2, one line", rc == 2 and len(err.strip().splitlines()) == 1,
          "%d %r" % (rc, err))
    rc, out, err = run([a.gather, "run", plan, "--out", os.path.join(tmp, "bad2"), "--robots", "external"])
    check("--robots external without --lcm: exit 2", rc == 2 and "needs --lcm" in err, "%d %r" % (rc, err))

    failed = results.count(False)
    print("robots_e2e: %d checks, %d failed" % (len(results), failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
