#!/usr/bin/env python3
"""The README's first-screen pictures (make readme-figures).

For the default scenario of `make run` (or SCENARIO):

1. docs/readme_fig3.png: Fig. 3 of the seed for it, the planner's estimate E
   beside the simulation R over the 27 configurations (`gather plan`, then
   `gather sim PLAN --all-configs --seeds SEEDS`): the refresh time the
   scenario's planner weighs, and the utility U that picks the plan.
2. docs/readme_mission.png: RViz on the mission (`mission.launch plan:=PLAN
   rviz:=true`, at RATE x real time), taken AT seconds of mission time in.

Must run inside a private network namespace (the mission's LCM multicast and
its ROS master), on an X display, with the workspace sourced; the Makefile
target does all three:
  tools/netns-run xvfb-run -a -s "-screen 0 1400x900x24" bash -c \\
    'source catkin_ws/devel/setup.bash && python3 tools/readme_figures.py'
Exit status 0 with both pictures written, 1 when a step fails (one line).
"""
import argparse
import os
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import yaml
from PIL import Image

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
GATHER = os.path.join(REPO, "catkin_ws", "devel", "lib", "gather_core", "gather")
DEFAULT_SCENARIO = os.path.join(REPO, "maps", "campus_busy.scenario.yaml")
RVIZ_BACKGROUND = (48, 48, 56)  # mission.rviz's 3D view


def die(msg):
    print("readme_figures: " + msg, file=sys.stderr)
    sys.exit(1)


def run(args, what):
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        last = (p.stdout.strip().splitlines() or [""])[-1]
        die("%s failed (exit %d): %s" % (what, p.returncode, last))
    return p.stdout


def side_by_side(paths, out, width):
    images = [Image.open(p).convert("RGB") for p in paths]
    h = max(i.height for i in images)
    canvas = Image.new("RGB", (sum(i.width for i in images), h), "white")
    x = 0
    for i in images:
        canvas.paste(i, (x, 0))
        x += i.width
    canvas = canvas.resize((width, round(canvas.height * width / canvas.width)), Image.LANCZOS)
    canvas.save(out, optimize=True)


def screenshot(path):
    subprocess.run(["import", "-window", "root", path], check=True, timeout=30)
    return np.asarray(Image.open(path).convert("RGB")).astype(int)


def rviz_on_screen(img):
    return int((np.abs(img - np.array(RVIZ_BACKGROUND)).max(axis=2) <= 4).sum()) > 20000


def crop_view(img):
    """RViz's 3D view alone (its panels and tool bar cropped: the columns and
    rows mostly of its background), then what is drawn in it (the map, the
    status line, the legend) with a margin."""
    a = np.asarray(img).astype(int)
    bg = np.abs(a - np.array(RVIZ_BACKGROUND)).max(axis=2) <= 4
    cols, rows = np.nonzero(bg.mean(axis=0) > 0.3)[0], np.nonzero(bg.mean(axis=1) > 0.3)[0]
    if len(cols) and len(rows):
        x0, x1, y0, y1 = cols.min(), cols.max() + 1, rows.min(), rows.max() + 1
        ys, xs = np.nonzero(~bg[y0:y1, x0:x1])
        if len(xs):
            m = 12
            x0, x1 = x0 + max(0, xs.min() - m), x0 + min(x1 - x0, xs.max() + 1 + m)
            y0, y1 = y0 + max(0, ys.min() - m), y0 + min(y1 - y0, ys.max() + 1 + m)
        img = img.crop((int(x0), int(y0), int(x1), int(y1)))
    return img


def mission_picture(plan, out_dir, rate, at, png, width):
    """RViz on the mission, AT seconds of mission time in, into png."""
    log_path = os.path.join(out_dir, "mission_launch.log")
    shot = os.path.join(out_dir, "rviz_full.png")
    args = ["roslaunch", "gather_oc", "mission.launch", "plan:=" + plan, "rviz:=true", "rate:=%g" % rate,
            "results_dir:=" + os.path.join(out_dir, "mission")]
    with open(log_path, "w") as log:
        p = subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT)
        try:
            t0 = time.time()
            while not rviz_on_screen(screenshot(shot)):  # its first start compiles shaders
                if p.poll() is not None or time.time() - t0 > 180:
                    die("RViz did not come up (%s)" % log_path)
                time.sleep(1.0)
            # The mission starts when every agent is ready; its clock runs at
            # `rate` from then on: wait for that, then AT / rate.
            while "mission starts" not in open(log_path).read():
                if time.time() - t0 > 240:
                    die("the fleet did not get ready (%s)" % log_path)
                if p.poll() is not None:
                    die("the mission ended before the picture (%s)" % log_path)
                time.sleep(0.5)
            time.sleep(at / rate)
            if p.poll() is not None:
                die("the mission ended before the picture (%s)" % log_path)
            screenshot(shot)
        finally:
            if p.poll() is None:
                p.send_signal(signal.SIGINT)
                try:
                    p.wait(60)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait()
    img = crop_view(Image.open(shot).convert("RGB"))
    img = img.resize((width, round(img.height * width / img.width)), Image.LANCZOS)
    img.save(png, optimize=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scenario", default=DEFAULT_SCENARIO)
    ap.add_argument("--out", default=os.path.join(REPO, "results", "readme"))
    ap.add_argument("--docs", default=os.path.join(REPO, "docs"))
    ap.add_argument("--seeds", type=int, default=3, help="simulated seeds per configuration for Fig. 3")
    ap.add_argument("--rate", type=float, default=20.0, help="the mission's pace, x real time")
    ap.add_argument("--at", type=float, default=700.0, help="mission time [s] of the RViz picture")
    a = ap.parse_args()
    if not os.path.isfile(a.scenario):
        die("no scenario %s" % a.scenario)
    if not (a.seeds >= 1 and a.rate > 0 and a.at > 0):
        die("--seeds must be >= 1, --rate and --at > 0")
    if not os.environ.get("DISPLAY"):
        die("no X display (run it under xvfb-run, as make readme-figures does)")
    shutil.rmtree(a.out, ignore_errors=True)
    os.makedirs(a.out)
    plan = os.path.join(a.out, "plan")
    best = run([GATHER, "plan", a.scenario, "--out", plan], "gather plan").strip().splitlines()
    print(best[-1] if best else "planned", flush=True)
    with open(a.scenario) as f:
        refresh = ((yaml.safe_load(f) or {}).get("planner") or {}).get("refresh", "interval")
    sim = os.path.join(a.out, "sim")
    run([GATHER, "sim", plan, "--all-configs", "--seeds", str(a.seeds), "--out", sim], "gather sim")
    fig3 = os.path.join(a.docs, "readme_fig3.png")
    side_by_side([os.path.join(sim, "fig3_refresh.png" if refresh == "latency" else "fig3_interval.png"),
                  os.path.join(sim, "fig3_utility.png")], fig3, 960)
    print("Fig. 3 (%s refresh, %d seeds) -> %s" % (refresh, a.seeds, fig3), flush=True)
    mission = os.path.join(a.docs, "readme_mission.png")
    mission_picture(plan, a.out, a.rate, a.at, mission, 800)
    print("RViz at %.0f s of mission time -> %s" % (a.at, mission), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
