#!/usr/bin/env python3
"""The team with every robot its own host (docs/robots.md, "Every robot its
own host"): run me under tools/hosts-run N, N = the plan's agents.

The OC (`gather run --lcm --clock wall`) runs on host `oc`, agent k on host
`rk` (each a network namespace on one bridge, UDP multicast with ttl=1
across the links, as on a radio network). Each agent's clock is put seconds
off (--clock-skew); the fleet runs on the OC's time, each agent measuring its
offset. In the middle of the mission one robot's link goes down for 30 s
(300 s of mission time at --rate 10). Checks: the mission completes, every agent measured its offset,
every goal ends in one final state, none lost with an agent, none recorded
twice, and what the partition cost against the same plan in one process
(lockstep, no partition) is printed. The OC's lcm-logger recording is
played back (gather run --replay, mission_bag into a bag for review.launch).
A second mission puts a robot on every host: the Python example driver
beside each agent (--motion lcm, the robot interface on ttl=0). Then the
same topology with a ttl=0 URL: the agents say in one line what is wrong
and exit 1.
"""
import argparse
import csv
import os
import re
import struct
import subprocess
import sys
import tempfile
import threading
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEVEL = os.path.join(REPO, "catkin_ws", "devel", "lib")
FAILURES = []
SKEWS = (-6.0, -3.0, 0.0, 3.0, 6.0)  # [s] agent k's clock: SKEWS[k % 5] off
FINAL = {"delivered", "expired", "dropped_overflow", "unreachable"}


def check(name, ok, detail=""):
    print(("PASS " if ok else "FAIL ") + name + ("" if ok or not detail else "\n     " + detail.replace("\n", "\n     ")))
    if not ok:
        FAILURES.append(name)
    return ok


def run(args, timeout=300):
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def agents_of(plan):
    """(id, role, collector) of every agent of plan.yaml."""
    out = []
    for line in open(os.path.join(plan, "plan.yaml")):
        m = re.match(r"\s*- \{id: (\d+), role: (\w+), segment: -?\d+, collector: (-?\d+)\}", line)
        if m:
            out.append((int(m.group(1)), m.group(2), int(m.group(3))))
    return out


def goals(path):
    return list(csv.DictReader(open(path)))


def check_bag(a, plan, key, logs, tmp, replayed_goals):
    """The recording into a bag for review.launch (mission_bag): what it
    holds, and that it tells the same mission as gather run --replay."""
    bag_dir = os.path.join(tmp, "bag")
    rc, out, err = run([a.mission_bag, plan, "--replay", ",".join(logs), "--key-file", key, "--out", bag_dir])
    if not check("mission_bag: the recording into a bag for review.launch (status %d)" % rc, rc == 0, err[-1000:]):
        return
    with open(os.path.join(bag_dir, "goals.csv")) as f, open(replayed_goals) as g:
        check("mission_bag: the same goals.csv as gather run --replay", f.read() == g.read())
    import rosbag  # Debian's python3-rosbag (gather_msgs types come from the bag's own definitions)
    path = os.path.join(bag_dir, "mission.bag")
    bag = rosbag.Bag(path)
    topics = bag.get_type_and_topic_info().topics
    want = ["/map", "/clock", "/tf", "/gather/plan_markers", "/gather/team_markers", "/gather/goal_markers",
            "/gather/path_markers", "/gather/status", "/gather/agents", "/gather/cycle", "/gather/agent_0/pose"]
    check("mission_bag: the topics mission.launch record:=true records", all(t in topics for t in want),
          "missing: %s" % [t for t in want if t not in topics])
    latched = set()
    for c in bag._get_connections():
        if c.header.get("latching") in (b"1", "1"):
            latched.add(c.topic)
    check("mission_bag: the map and the plan's markers are latched (review_player shows them from any start)",
          {"/map", "/gather/plan_markers", "/gather/status"} <= latched, sorted(latched))
    statuses = [m for _, m, _ in bag.read_messages(topics=["/gather/status"])]
    cycles = sum(1 for _ in bag.read_messages(topics=["/gather/cycle"]))
    rows = goals(os.path.join(bag_dir, "goals.csv"))
    delivered = sum(r["state"] == "delivered" for r in rows)
    last = statuses[-1] if statuses else None
    check("mission_bag: its last status says done, %d delivered, %d cycles (goals.csv: %d)"
          % (last.delivered if last else -1, cycles, delivered),
          last is not None and last.state == "done" and last.delivered == delivered and cycles == last.cycles,
          str(last)[:400])
    clocks = [m.clock.to_sec() for _, m, _ in bag.read_messages(topics=["/clock"])]
    check("mission_bag: /clock is the mission's time, from 0 to its end (%.0f s)" % (clocks[-1] if clocks else -1),
          clocks and clocks[0] == 0 and all(b >= c for c, b in zip(clocks, clocks[1:])) and
          abs(clocks[-1] - last.time) < 1.0)
    bag.close()
    # A recording cut in the middle: status 1, and the bag holds the mission up to there.
    cut = os.path.join(tmp, "cut_for_bag.lcmlog")
    with open(logs[0], "rb") as f, open(cut, "wb") as g:
        g.write(f.read(os.path.getsize(logs[0]) // 2))
    cut_dir = os.path.join(tmp, "bag_cut")
    rc, _, err = run([a.mission_bag, plan, "--replay", cut + "," + logs[1], "--key-file", key, "--out", cut_dir])
    kept = os.path.join(cut_dir, "mission.bag")
    end = rosbag.Bag(kept).get_end_time() if os.path.exists(kept) else -1
    check("mission_bag of a recording cut short: status 1, the bag kept up to the cut (%.0f s)" % end,
          rc == 1 and "before the mission did" in err and kept in err and 0 < end < clocks[-1] - 60,
          "status %d: %s" % (rc, err))
    rc, _, err = run([a.mission_bag, plan, "--replay", ",".join(logs), "--out", cut_dir])
    check("mission_bag without a key: status 2, one line", rc == 2 and err.count("\n") == 1, err)


def robots_on_hosts(a, plan, key, tmp, ref_rows):
    """Each robot host runs its agent and its robot's driver (the Python
    example driver, src/gather_agent/examples/robot_driver.py): the robot
    interface stays on the host (ttl=0), the fleet crosses the bridge."""
    import yaml
    scenario = yaml.safe_load(open(os.path.join(REPO, "maps", "office.scenario.yaml")))
    ox, oy = scenario["oc"]
    speed = scenario["team"]["speed"]
    driver = os.path.join(REPO, "src", "gather_agent", "examples", "robot_driver.py")
    robot_url = "udpm://239.255.76.67:7669?ttl=0"
    cycles, rate = 1, 8.0
    wrapper = os.path.join(tmp, "robot_on_its_host.sh")
    with open(wrapper, "w") as f:
        f.write("#!/bin/bash\n# gather run starts agent k as: $0 --id k ...: on host rk its robot's driver, then it.\n"
                "id=$2\nexport PYTHONPATH=%s\n"
                "host-exec r$id %s %s --id $id --start %g,%g --speed %g --key-file %s --lcm-url '%s' "
                "--time-scale %g --duration 600 2>/dev/null &\ndriver=$!\n"
                "host-exec r$id %s \"$@\" --robot-url '%s' --silence 300\nrc=$?\n"
                "kill $driver 2>/dev/null\nwait $driver\nexit $rc\n"
                % (os.path.abspath(a.pylcm), sys.executable, driver, ox, oy, speed, key, robot_url, rate, a.agent,
                   robot_url))
    os.chmod(wrapper, 0o755)
    out_dir = os.path.join(tmp, "robots")
    t0 = time.time()
    rc, out, err = run(["host-exec", "oc", a.gather, "run", plan, "--out", out_dir, "--cycles", str(cycles), "--lcm",
                        "--key-file", key, "--lcm-url", "udpm://239.255.76.67:7667?ttl=1", "--clock", "wall",
                        "--rate", str(rate), "--robots", "external", "--agent-bin", wrapper], timeout=600)
    if not check("robots on their hosts: each host its agent and its robot's driver, the mission completes "
                 "(status %d, %.0f s)" % (rc, time.time() - t0), rc == 0, (out + err)[-2000:]):
        return
    rows = goals(os.path.join(out_dir, "goals.csv"))
    states = {}
    for r in rows:
        states[r["state"]] = states.get(r["state"], 0) + 1
    check("robots on their hosts: every goal once, in a final state %s, none lost" % states,
          len({r["goal"] for r in rows}) == len(rows) and set(states) <= FINAL and "lost_with_agent" not in states)
    # (A wall-clock run keeps no per-agent counters: a measured goal is one its robot drove to.)
    workers = {r["worker"] for r in rows}
    measured = {r["measured_by"] for r in rows if r["measured_by"] != "-1"}
    check("robots on their hosts: the robots of %d of %d workers with goals drove to them and measured"
          % (len(measured & workers), len(workers)), len(measured & workers) >= len(workers) // 2)
    got = states.get("delivered", 0)
    want = sum(r["state"] == "delivered" and int(r["cycle"]) < cycles for r in ref_rows)
    check("robots on their hosts: %d goals delivered, ideal bases in one process %d (the first %d cycles)"
          % (got, want, cycles), 2 * got >= want)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gather", default=os.path.join(DEVEL, "gather_core", "gather"))
    ap.add_argument("--agent", default=os.path.join(DEVEL, "gather_agent", "gather_agent"))
    ap.add_argument("--mission-bag", default=os.path.join(DEVEL, "gather_oc", "mission_bag"))
    ap.add_argument("--pylcm", default=os.path.join(REPO, "build", "pylcm"),
                    help="the lcm package and lcm-gen --python types (make pylcm), for the example driver")
    ap.add_argument("--config", default="pap:4")
    ap.add_argument("--rate", type=float, default=10.0, help="mission seconds per wall second")
    ap.add_argument("--cycles", type=int, default=6)
    ap.add_argument("--down-at", type=float, default=10.0, help="[s of wall time after the start] the link goes down")
    ap.add_argument("--down-for", type=float, default=30.0, help="[s of wall time]")
    ap.add_argument("--keep", default="", help="keep the run's files here")
    a = ap.parse_args()
    hosts = os.environ.get("GATHER_HOSTS", "").split()
    if not hosts:
        print("hosts_e2e: run me under tools/hosts-run N (N = the plan's agents)", file=sys.stderr)
        return 2
    tmp = a.keep or tempfile.mkdtemp(prefix="gather_hosts_e2e_")
    os.makedirs(tmp, exist_ok=True)
    key = os.path.join(tmp, "fleet.key")
    if not os.path.exists(key):
        run([a.gather, "keygen", key])
    plan = os.path.join(tmp, "plan")
    rc, out, err = run([a.gather, "plan", os.path.join(REPO, "maps", "office.scenario.yaml"), "--config", a.config,
                        "--association", "off", "--out", plan])
    if not check("plan office %s" % a.config, rc == 0, err):
        return 1
    agents = agents_of(plan)
    if not check("one robot host per agent (%d agents, hosts %s)" % (len(agents), " ".join(hosts)),
                 len(hosts) == len(agents) + 1 and hosts[0] == "oc"):
        return 1
    # The robot whose link goes down: a worker of a collector if the plan has
    # one (its data travels two hops), else the first worker.
    workers = [i for i, role, c in agents if role == "worker"]
    of_collector = [i for i, role, c in agents if role == "worker" and c >= 0]
    victim = (of_collector or workers)[0]

    # Every agent on its own host, its clock off by SKEWS[k % 5].
    wrapper = os.path.join(tmp, "agent_on_its_host.sh")
    with open(wrapper, "w") as f:
        f.write("#!/bin/bash\n# gather run starts agent k as: $0 --id k ...: run it on host rk, its clock off.\n"
                "skews=(%s)\nid=$2\nexec host-exec r$id %s \"$@\" --clock-skew ${skews[$((id %% %d))]} --silence 300\n"
                % (" ".join("%g" % s for s in SKEWS), a.agent, len(SKEWS)))
    os.chmod(wrapper, 0o755)
    url = "udpm://239.255.76.67:7667?ttl=1"
    out_dir = os.path.join(tmp, "run")
    cmd = ["host-exec", "oc", a.gather, "run", plan, "--out", out_dir, "--cycles", str(a.cycles), "--lcm",
           "--key-file", key, "--lcm-url", url, "--clock", "wall", "--rate", str(a.rate), "--agent-bin", wrapper]
    print("the OC on host oc, %d agents on hosts r0..r%d (clocks off by %s s), robot %d's link down from %g s for %g s"
          % (len(agents), len(agents) - 1, "/".join("%+g" % s for s in SKEWS), victim, a.down_at, a.down_for))
    # What the fleet said, recorded at the OC's host (docs/robots.md, "Recording what the fleet said").
    logs = [os.path.join(tmp, "fleet.lcmlog"), os.path.join(tmp, "replies.lcmlog")]
    loggers = [subprocess.Popen(["host-exec", "oc", "lcm-logger", "-f", "--lcm-url=" + u, f],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
               for u, f in ((url, logs[0]), ("udpm://239.255.76.67:7668?ttl=1", logs[1]))]
    time.sleep(0.5)
    t0 = time.time()
    oc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    partition = {}

    def cut():
        time.sleep(a.down_at)
        if oc.poll() is None:
            partition["down"] = time.time() - t0
            subprocess.run(["host-link", "r%d" % victim, "down"], check=True)
            time.sleep(a.down_for)
            subprocess.run(["host-link", "r%d" % victim, "up"], check=True)
            partition["up"] = time.time() - t0

    cutter = threading.Thread(target=cut)
    cutter.start()
    try:
        stdout, stderr = oc.communicate(timeout=a.down_at + a.down_for + a.cycles * 200.0 / a.rate + 300)
    except subprocess.TimeoutExpired:
        oc.kill()
        stdout, stderr = oc.communicate()
    cutter.join()
    wall = time.time() - t0
    time.sleep(0.5)
    for p in loggers:
        p.terminate()
        p.wait()
    if not check("the mission over %d hosts completes (status %d, %.0f s)" % (len(hosts), oc.returncode, wall),
                 oc.returncode == 0, (stdout[-1500:] + stderr[-1500:])):
        return 1
    check("the link was down in the middle of the mission (%.0f s to %.0f s of %.0f s)"
          % (partition.get("down", -1), partition.get("up", -1), wall),
          "up" in partition and partition["up"] < wall - 10)
    # Each agent measured its clock's offset to the OC.
    # Within 50 ms, or within half its best round trip (the bound of a
    # two-way exchange: on a loaded machine the first exchanges are slow).
    offsets = {int(m.group(1)): (float(m.group(2)), float(m.group(3)) / 1000.0)
               for m in re.finditer(r"gather_agent (\d+): clock offset to the OC ([-+0-9.]+) s "
                                    r"\(round trip ([0-9.]+) ms\)", stdout)}
    wrong = {k: v for k, (v, rtt) in offsets.items() if abs(v + SKEWS[k % len(SKEWS)]) > max(0.05, rtt / 2 + 0.002)}
    check("every agent measured its clock's offset to the OC within 50 ms or half its round trip (%d of %d)"
          % (len(offsets), len(agents)),
          len(offsets) == len(agents) and not wrong,
          "off: %s\n%s" % (wrong, "\n".join(l for l in stdout.splitlines() if "clock" in l)))
    # The OC refused nothing: every agent signed on the OC's time, whatever its host's clock.
    rejected = list(csv.DictReader(open(os.path.join(out_dir, "oc_rejected.csv"))))[0]
    bad = {k: v for k, v in rejected.items() if k.startswith("rejected_") and v != "0"}
    check("the OC refused no agent's message (signing on the corrected clocks)", not bad, str(bad))
    # Every goal once, in one final state; none lost.
    rows = goals(os.path.join(out_dir, "goals.csv"))
    ids = [r["goal"] for r in rows]
    check("every goal recorded once (%d goals)" % len(ids), len(ids) == len(set(ids)) and len(ids) > 0)
    states = {}
    for r in rows:
        states[r["state"]] = states.get(r["state"], 0) + 1
    check("every goal in a final state %s" % states, set(states) <= FINAL)
    check("none lost with an agent", states.get("lost_with_agent", 0) == 0)
    bad = [r["goal"] for r in rows if r["state"] == "delivered" and (r["delivered_by"] == "-1" or r["measured_by"] == "-1")]
    check("every delivered goal has its measurement and its delivery", not bad, str(bad[:10]))
    # What the partition cost: against the same plan in one process.
    ref_dir = os.path.join(tmp, "reference")
    rc, _, err = run([a.gather, "run", plan, "--out", ref_dir, "--cycles", str(a.cycles)])
    if check("the same plan in one process (lockstep, no partition)", rc == 0, err):
        ref = goals(os.path.join(ref_dir, "goals.csv"))
        check("the same goals requested (%d)" % len(ref), sorted(r["goal"] for r in ref) == sorted(ids))
        got = sum(r["state"] == "delivered" for r in rows)
        want = sum(r["state"] == "delivered" for r in ref)
        seg = {r["goal"]: r["worker"] for r in ref}
        mine_ref = sum(r["state"] == "delivered" and r["worker"] == str(victim) for r in ref)
        mine = sum(r["state"] == "delivered" and seg.get(r["goal"]) == str(victim) for r in rows)
        by_victim = [r for r in rows if r["measured_by"] == str(victim)]
        print("partition cost: %d goals delivered over the hosts against %d in one process (%+d); of robot %d's "
              "segment %d against %d; robot %d measured %d goals, %d of them delivered"
              % (got, want, got - want, victim, mine, mine_ref, victim, len(by_victim),
                 sum(r["state"] == "delivered" for r in by_victim)))
        check("the partition cost at most robot %d's own goals plus 10%% of the rest" % victim,
              want - got <= mine_ref + 0.1 * want, "%d delivered against %d" % (got, want))

        robots_on_hosts(a, plan, key, tmp, ref)

    # The recording played back: the OC's role again on what it heard, the same goals.csv.
    replay_dir = os.path.join(tmp, "replay")
    rc, out, err = run([a.gather, "run", plan, "--out", replay_dir, "--lcm", "--key-file", key, "--replay",
                        ",".join(logs)])
    if check("gather run --replay of lcm-logger's recordings (%s)" % (out.strip().splitlines() or ["?"])[-2:-1],
             rc == 0, err[-1000:]):
        again = {r["goal"]: r["state"] for r in goals(os.path.join(replay_dir, "goals.csv"))}
        same = sum(again.get(r["goal"]) == r["state"] for r in rows)
        check("played back: %d of %d goals end as in the mission" % (same, len(rows)),
              len(again) == len(rows) and same >= 0.98 * len(rows))
    check_bag(a, plan, key, logs, tmp, os.path.join(replay_dir, "goals.csv"))
    rc, _, err = run([a.gather, "run", plan, "--out", replay_dir, "--lcm", "--key-file", key, "--replay",
                      os.path.join(tmp, "nothing.lcmlog")])
    check("--replay of a log that is not there: status 2, one line naming it",
          rc == 2 and err.count("\n") == 1 and "nothing.lcmlog" in err, err)
    cut = os.path.join(tmp, "cut.lcmlog")  # the fleet's recording cut in the middle of the mission
    with open(logs[0], "rb") as f, open(cut, "wb") as g:
        g.write(f.read(os.path.getsize(logs[0]) // 2))
    rc, _, err = run([a.gather, "run", plan, "--out", replay_dir, "--lcm", "--key-file", key, "--replay",
                      cut + "," + logs[1]])
    check("--replay of a recording cut short: status 1, it says where it ends (no made-up losses)",
          rc == 1 and "before the mission did" in err and "cut.lcmlog" in err, "status %d: %s" % (rc, err))
    damaged = os.path.join(tmp, "damaged.lcmlog")  # an event that says it holds 2 GB
    with open(damaged, "wb") as f:
        f.write(struct.pack(">IqqII", 0xEDA1DA01, 0, 1, 10, 0x7FFFFFFF) + b"GATHER_ACK" + b"x" * 100)
    rc, _, err = run([a.gather, "run", plan, "--out", replay_dir, "--lcm", "--key-file", key, "--replay", damaged])
    check("--replay of a damaged log: status 2, one line naming it, nothing allocated for it",
          rc == 2 and err.count("\n") == 1 and "damaged.lcmlog" in err, err)
    rc, _, err = run([a.gather, "run", plan, "--out", replay_dir, "--lcm", "--key-file", key, "--replay",
                      ",".join(logs), "--cycles", "2"])
    check("--replay with a setting of its own: status 2, one line", rc == 2 and "--replay takes" in err, err)

    # The same topology, a ttl=0 URL: nothing crosses a link. Each agent says
    # what is wrong in one line and exits 1 (an agent on r0 alone is enough).
    oc_side = subprocess.Popen(["host-exec", "oc", a.gather, "run", plan, "--out", os.path.join(tmp, "ttl0"), "--lcm",
                                "--key-file", key, "--lcm-url", "udpm://239.255.76.67:7667?ttl=0", "--clock", "wall",
                                "--cycles", "1", "--agent-bin", "/bin/true"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # Robot 0 with its own keys, as deployed (gather keygen --agent).
    agent_key = os.path.join(tmp, "agent0.key")
    if not os.path.exists(agent_key):
        krc, _, kerr = run([a.gather, "keygen", agent_key, "--agent", "0", "--plan", plan, "--master", key])
        check("gather keygen --agent 0: its own key file, mode 0600",
              krc == 0 and (os.stat(agent_key).st_mode & 0o777) == 0o600, kerr)
    time.sleep(1.0)  # the OC announces its plan (on its own host only)
    rc, out, err = run(["host-exec", "r0", a.agent, "--id", "0", "--plan", plan, "--key-file", agent_key,
                        "--lcm-url", "udpm://239.255.76.67:7667?ttl=0", "--silence", "3"], timeout=60)
    oc_side.kill()
    oc_side.communicate()
    lines = [l for l in err.splitlines() if l.startswith("gather_agent 0:")]
    check("ttl=0 across hosts: the agent exits 1 with one line naming the URL and ttl=0",
          rc == 1 and len(lines) == 1 and "ttl=0" in lines[0] and "udpm://239.255.76.67:7667?ttl=0" in lines[0],
          "status %d: %s" % (rc, err[-800:]))
    print("hosts_e2e: %d failed" % len(FAILURES) if FAILURES else "hosts_e2e: all passed")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
