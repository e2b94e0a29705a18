#!/usr/bin/env python3
"""A radio link that reorders (docs/security.md, "What a receiver checks"):
it joins two LCM URLs, the OC's side A and the agents' side B, and passes
every fleet message from one side to the other, holding it up to --hold-ms
and letting the messages it holds go in a random order. Run it inside
tools/netns-run (UDP multicast in a private namespace only).

It reads each message's envelope (fleet_envelope_t: sender, counter) and
counts the messages it let go after a newer one of the same sender on the
same channel: those a receiver without a reorder window would drop as
replayed. With --duplicate P it also sends a fraction P of the OC's
messages to the agents a second time (a replay each of their receivers
must refuse), and counts them per receiver. On SIGTERM or SIGINT it
writes what it counted to --report (YAML) and exits 0.

  reorder_link.py --a udpm://239.255.76.67:7667?ttl=0 --b udpm://239.255.76.68:7677?ttl=0 \\
      --report link.yaml [--hold-ms 3] [--duplicate 0.01] [--seed 1]

Needs the lcm package and the gather_lcm Python types (make pylcm:
PYTHONPATH=build/pylcm).
"""
import argparse
import hashlib
import random
import select
import signal
import sys
import time

import lcm
from gather_lcm import fleet_envelope_t

# The channels the OC and the agents talk on (the radio and the lockstep
# clock); the tick replies have their own URL and do not cross the link.
CHANNELS = "GATHER_.*"


class Side:
    def __init__(self, name, url):
        self.name = name
        self.lc = lcm.LCM(url)
        self.held = []  # (due, channel, data) bound for this side
        self.echo = {}  # digest -> count of messages this link published here (it hears them back)
        self.newest = {}  # (channel, sender) -> the newest counter let go here
        self.passed = 0
        self.out_of_order = 0
        self.duplicated = 0
        self.replays_for = {}  # receiver id -> duplicates sent here that carry a tag for it


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--a", required=True, help="LCM URL of the OC's side")
    ap.add_argument("--b", required=True, help="LCM URL of the agents' side")
    ap.add_argument("--report", required=True, help="YAML file written on exit")
    ap.add_argument("--hold-ms", type=float, default=3.0, help="[ms] the longest a message is held, > 0")
    ap.add_argument("--duplicate", type=float, default=0.0, help="fraction of messages sent twice, [0, 1)")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    if not a.hold_ms > 0 or not 0 <= a.duplicate < 1:
        print("reorder_link: --hold-ms must be > 0 and --duplicate in [0, 1)", file=sys.stderr)
        return 2
    rng = random.Random(a.seed)
    sides = {"a": Side("a", a.a), "b": Side("b", a.b)}
    other = {"a": sides["b"], "b": sides["a"]}
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))

    def heard(side):
        def on(channel, data):
            d = hashlib.blake2b(channel.encode() + b"\0" + data, digest_size=16).digest()
            n = side.echo.get(d, 0)
            if n:  # what this link published on this side, heard back
                if n == 1:
                    del side.echo[d]
                else:
                    side.echo[d] = n - 1
                return
            to = other[side.name]
            to.held.append((time.monotonic() + rng.uniform(0, a.hold_ms) / 1000.0, channel, data, d))
        return on

    for s in sides.values():
        s.lc.subscribe(CHANNELS, heard(s))

    def envelope(data):
        try:
            return fleet_envelope_t.decode(data)
        except Exception:  # not an envelope: passed on as it is
            return None

    def publish(to, channel, data, d):
        to.echo[d] = to.echo.get(d, 0) + 1
        to.lc.publish(channel, data)
        e = envelope(data)
        if e is not None:
            key = (channel, e.sender)
            if e.counter < to.newest.get(key, -1):
                to.out_of_order += 1
            to.newest[key] = max(to.newest.get(key, -1), e.counter)
        return e

    fds = {s.lc.fileno(): s for s in sides.values()}
    while not stop:
        due = [m[0] for s in sides.values() for m in s.held]
        wait = max(0.0, min(due) - time.monotonic()) if due else 0.05
        try:
            ready, _, _ = select.select(list(fds), [], [], wait)
        except InterruptedError:
            continue
        for fd in ready:
            fds[fd].lc.handle()
        now = time.monotonic()
        for s in sides.values():
            if not s.held:
                continue
            # What is due goes, in a random order: a message held longer
            # than a newer one arrives after it.
            go = [m for m in s.held if m[0] <= now]
            if not go:
                continue
            s.held = [m for m in s.held if m[0] > now]
            rng.shuffle(go)
            for _, channel, data, d in go:
                e = publish(s, channel, data, d)
                s.passed += 1
                if s.name == "b" and e is not None and e.sender == -1 and a.duplicate and rng.random() < a.duplicate:
                    publish(s, channel, data, d)
                    s.duplicated += 1
                    for r in e.receiver:
                        s.replays_for[r] = s.replays_for.get(r, 0) + 1
    with open(a.report, "w") as f:
        for s in sides.values():
            f.write("to_%s: {passed: %d, out_of_order: %d, duplicated: %d}\n"
                    % (s.name, s.passed, s.out_of_order, s.duplicated))
        f.write("replays_for: {%s}\n" % ", ".join("%d: %d" % kv for kv in sorted(sides["b"].replays_for.items())))
    return 0


if __name__ == "__main__":
    sys.exit(main())
